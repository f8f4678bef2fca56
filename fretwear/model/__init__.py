"""The structure: one linear model type with contacts of every kind (paper eq. 5, 17-23, 30), model files.

``fretwear.model.structure`` defines :class:`~fretwear.model.Model` and its 1-D contacts and
the paper's 2-DOF example; ``fretwear.model.pairs`` the contact node pairs of
an interface (:class:`ContactPairs`); ``fretwear.model.reduction`` the
Craig-Bampton reduction of a model (:func:`craig_bampton`, a :class:`~fretwear.model.Model` in,
a :class:`~fretwear.model.Model` out); ``fretwear.model.disk`` the lumped bladed disk
(:func:`bladed_disk`, its cyclic sector :class:`~fretwear.model.DiskSector`); ``fretwear.model.modelfile``
reads and writes models as TOML (:func:`read_model`).
"""

from .disk import DiskSector, bladed_disk
from .modelfile import ModelFileError, dump_model, read_model
from .pairs import ContactPairs
from .reduction import Reduction, craig_bampton
from .structure import (
    OPEN,
    SLIP,
    STICK,
    FrictionContact,
    Model,
    NormalContact,
    jenkins_oscillator,
    paper_model,
)

__all__ = [
    "OPEN",
    "SLIP",
    "STICK",
    "ContactPairs",
    "DiskSector",
    "FrictionContact",
    "Model",
    "ModelFileError",
    "NormalContact",
    "Reduction",
    "bladed_disk",
    "craig_bampton",
    "dump_model",
    "jenkins_oscillator",
    "paper_model",
    "read_model",
]
