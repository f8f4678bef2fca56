"""The scenes, one module each: what each computes (``Scene.needs``), draws, explains and exports.

The tabs of the session's scenes (:data:`SCENES`, in tab order) share the base
:class:`~app.scenes.base.Scene`; the Interface and Study tabs
(:mod:`app.scenes.interface`, :mod:`app.scenes.study`) have controls of their
own and are imported by the page that shows them.
"""

from .accuracy import QUANTITY_LABELS, TARGETS, AccuracyScene, sidebar_equivalent
from .base import Scene, Selection
from .cycle import ANIMATION_FRAMES, CycleScene
from .evolution import EvolutionScene
from .methods import MethodsScene
from .regimes import RegimesScene
from .wear_map import WearMapScene

__all__ = [
    "ANIMATION_FRAMES",
    "QUANTITY_LABELS",
    "SCENES",
    "TARGETS",
    "AccuracyScene",
    "CycleScene",
    "EvolutionScene",
    "MethodsScene",
    "RegimesScene",
    "Scene",
    "Selection",
    "WearMapScene",
    "sidebar_equivalent",
]

#: the scenes in tab order
SCENES: tuple[type[Scene], ...] = (
    RegimesScene,
    WearMapScene,
    EvolutionScene,
    CycleScene,
    MethodsScene,
    AccuracyScene,
)
