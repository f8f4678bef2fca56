"""The structure: one linear model type with contacts of every kind (paper eq. 5, 17-23, 30), model files.

:mod:`~fretwear.model.structure` defines :class:`Model` and its 1-D contacts and
the paper's 2-DOF example; :mod:`~fretwear.model.pairs` the contact node pairs of
an interface (:class:`ContactPairs`); :mod:`~fretwear.model.reduction` the
Craig-Bampton reduction of a model (:func:`craig_bampton`, a :class:`Model` in,
a :class:`Model` out); :mod:`~fretwear.model.disk` the lumped bladed disk
(:func:`bladed_disk`, its cyclic sector :class:`DiskSector`); :mod:`~fretwear.model.modelfile`
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
