"""The bladed disk beyond its model (:func:`fretwear.bladed_disk`): cyclic symmetry and mistuning.

* ``fretwear.disk.cyclic``: the tuned disk with its shroud solved on one
  sector (harmonic balance with the cyclic condition), equal to the full disk.
* ``fretwear.disk.mistuning``: linear forced response of mistuned disks by
  modal superposition, amplitude magnification factors and Whitehead's bound.
"""

from .cyclic import samples_for, solve_sector, sweep_sector
from .mistuning import Magnification, draw_mistuning, magnification, modal_basis, peak

__all__ = [
    "Magnification", "draw_mistuning", "magnification", "modal_basis", "peak", "samples_for", "solve_sector",
    "sweep_sector",
]  # fmt: skip
