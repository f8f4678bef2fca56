"""The dashboard in a Jupyter notebook: :func:`page` returns the whole page, or one scene, as a Panel object.

Run the notebook from the repository's root (``app`` is not installed with the
wheel): the page is the served dashboard's (:func:`app.page.build_page`),
its sidebar and tabs side by side in the cell's output.
"""

from __future__ import annotations

from concurrent.futures import Executor
from functools import partial
from typing import Any

import panel as pn

from fretwear import figures

from .backend import shared_executor
from .live import SIDEBAR_WIDTH, run_status
from .page import ExportSettings, _export_card, _scene_tab, _sidebar, build_page
from .scenes import SCENES
from .scenes.disk import DiskScene, disk_tab
from .scenes.interface import InterfaceScene, interface_tab
from .scenes.study import StudyScene, study_tab
from .session import Session

__all__ = ["SCENE_KEYS", "page"]

#: the keys of the scenes :func:`page` shows alone: the session's tabs, then the tabs of their own
SCENE_KEYS: tuple[str, ...] = (*(s.key for s in SCENES), "interface", "disk", "study")


def page(
    scene: str | None = None,
    query: str = "",
    *,
    study: str | None = None,
    interface_model: str | None = None,
    executor: Executor | None = None,
) -> pn.viewable.Viewable:
    """The dashboard for a notebook cell: the whole page, or the tab of one scene with the sidebar.

    Parameters
    ----------
    scene : str, optional
        One of :data:`SCENE_KEYS` (``"regimes"``, ``"wearmap"``, ..., ``"interface"``,
        ``"disk"``, ``"study"``) to show that tab alone; ``None``: the whole page.
    query : str
        Settings as in the served page's address, keyed like the CLI options
        (``"fex=14&mu=0.8&f=0.7"``); a problem with them is shown as the page's notice.
    study : str, optional
        A study store (``fretwear study ... --out RESULT.zarr``) for the Study tab.
    interface_model : str, optional
        A model file offered by the Interface tab.
    executor : Executor, optional
        Where the computations run; default the dashboard's shared threads
        (the cell returns at once and the figures fill in as results arrive).

    Returns
    -------
    panel.viewable.Viewable
        A ``panel.Row`` (sidebar, then the page's tabs or the scene's tab).

    Raises
    ------
    ValueError
        For a ``scene`` that is not one of :data:`SCENE_KEYS`.

    Examples
    --------
    In a notebook started in the repository's root::

        import panel as pn
        from app.notebook import page

        pn.extension()
        page()                              # the whole dashboard
        page("wearmap", "fex=14&mu=0.8")    # the wear map of the paper's 14 N case alone
    """
    if scene is not None and scene not in SCENE_KEYS:
        raise ValueError(f"scene must be None or one of {', '.join(SCENE_KEYS)}, got {scene!r}")
    executor = shared_executor() if executor is None else executor
    session = Session(executor=executor, start=False)
    own = {
        "interface": InterfaceScene(interface_model, tasks=session.tasks, executor=executor,
                                    dispatch=session.dispatch),
        "disk": DiskScene(tasks=session.tasks, executor=executor, dispatch=session.dispatch),
        "study": StudyScene(study, tasks=session.tasks),
    }  # fmt: skip
    if scene in session.scenes:
        session.scene = scene
    session.start(session.apply_query(query) if query else [])
    tabs = {"interface": interface_tab, "disk": disk_tab, "study": study_tab}
    width = dict(width=SIDEBAR_WIDTH)
    if scene is None:
        extra = tuple(
            (title, lambda card, key=key: tabs[key](own[key], card), own[key])
            for title, key in (("Interface", "interface"), ("Bladed disk", "disk"), ("Study", "study"))
        )
        template = build_page(session, None, extra)
        return pn.Row(pn.Column(*template.sidebar, **width), *template.main, sizing_mode="stretch_width")
    figures.load_backend("bokeh")
    export = ExportSettings()
    if scene in session.scenes:
        content = [run_status(session), *_scene_tab(session.scenes[scene], session, export)]
    else:
        content = tabs[scene](own[scene], partial(_export_card, settings=export))
    sidebar: list[Any] = _sidebar(session) if scene in session.scenes else []
    return pn.Row(
        *([pn.Column(*sidebar, **width)] if sidebar else []),
        pn.Column(*content, sizing_mode="stretch_width"),
        sizing_mode="stretch_width",
    )
