"""The structure: linear dynamics with friction and unilateral contacts (paper eq. 5, 30), and model files.

:mod:`~fretwear.model.structure` defines :class:`Model` and its contacts and the
paper's 2-DOF example; :mod:`~fretwear.model.modelfile` reads and writes models as
TOML (:func:`read_model`).
"""

from .modelfile import ModelFileError, dump_model, read_model
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
    "FrictionContact",
    "Model",
    "ModelFileError",
    "NormalContact",
    "dump_model",
    "jenkins_oscillator",
    "paper_model",
    "read_model",
]
