"""The bladed disk beyond its model (:func:`fretwear.bladed_disk`): mistuning.

* :mod:`~fretwear.disk.mistuning`: linear forced response of mistuned disks by
  modal superposition, amplitude magnification factors and Whitehead's bound.
"""

from .mistuning import Magnification, draw_mistuning, magnification, modal_basis, peak

__all__ = ["Magnification", "draw_mistuning", "magnification", "modal_basis", "peak"]
