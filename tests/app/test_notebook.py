"""The dashboard in a notebook (app.notebook.page), built without a browser and without computing."""

import panel as pn
import pytest

from app.notebook import SCENE_KEYS, page


class Held:
    """An executor that keeps what it is given and runs none of it: the page is built, nothing computed."""

    def __init__(self):
        self.submitted = []

    def submit(self, fn, *args, **kwargs):
        from concurrent.futures import Future

        self.submitted.append(fn)
        return Future()


def test_the_whole_page_is_a_panel_viewable_with_the_sidebar_and_the_tabs():
    held = Held()
    view = page(executor=held)
    assert isinstance(view, pn.viewable.Viewable) and isinstance(view, pn.Row)
    tabs = view.select(pn.Tabs)
    assert len(tabs) == 1
    names = [t.name for t in tabs[0]]
    assert names[:2] == ["Regimes", "Wear map"]
    assert names[-4:] == ["Interface", "Bladed disk", "Study", "Glossary"]
    assert held.submitted  # the visible scene asked for its run
    assert view.get_root() is not None  # Bokeh models can be made: what a notebook cell displays


@pytest.mark.parametrize("scene", ["wearmap", "disk"])
def test_one_scene_alone_with_the_address_settings(scene):
    view = page(scene, "fex=14&mu=0.8", executor=Held())
    assert isinstance(view, pn.Row) and view.get_root() is not None
    assert not view.select(pn.Tabs)  # one scene: no tabs
    panes = view.select(pn.pane.HoloViews)
    assert panes  # its figures


def test_the_query_reaches_the_session_and_a_bad_scene_is_refused():
    held = Held()
    view = page("wearmap", "fex=14&mu=0.8", executor=held)
    session = held.submitted[0].func.__self__  # the run asked for: the session's, of the scene shown
    assert session.scene == "wearmap" and session.controls.fex == 14
    assert view.select(pn.widgets.TextInput)[0].value == "14"  # the F_ex box shows the address's value
    with pytest.raises(ValueError, match="scene must be None or one of regimes"):
        page("nope")
    assert "study" in SCENE_KEYS
