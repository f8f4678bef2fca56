"""The fretwear dashboard: ``panel serve app/app.py`` (user guide: ``docs/user_guide/dashboard.md``).

Bokeh executes this file for every new session: it builds a :class:`Session`
whose runs go to the server's shared threads and whose results come from the
process-wide cache, applies the settings of the page's address (URL query,
keyed like the CLI options), and builds the page around it. The first
execution starts the warm-up (:mod:`app.warmup`) in the background.
"""

import argparse
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# Bokeh puts app/ first on the path, where ``import app`` would find this file instead of the package:
# the repository root goes first (also when it is further down the path already)
if str(ROOT) in sys.path:
    sys.path.remove(str(ROOT))
sys.path.insert(0, str(ROOT))

import panel as pn  # noqa: E402

from app.backend import shared_executor  # noqa: E402
from app.page import apply_tab_address, build_page, document_dispatch  # noqa: E402
from app.scenes.disk import DiskScene, disk_tab  # noqa: E402
from app.scenes.interface import InterfaceScene, interface_tab  # noqa: E402
from app.scenes.study import StudyScene, study_tab  # noqa: E402
from app.session import Session  # noqa: E402
from app.warmup import warm_in_background  # noqa: E402

pn.extension(notifications=False)
# the wear histories keep their warnings (the two-scale assumption, a polynomial misfit) and the scenes
# show them as notes with their frequency: the server log need not repeat them as Python warnings
warnings.filterwarnings("ignore", category=RuntimeWarning, module=r"fretwear\.wear")
warm_in_background()
session = Session(executor=shared_executor(), dispatch=document_dispatch(pn.state.curdoc), start=False)
pn.state.on_session_destroyed(lambda _context, s=session: s.close())
# ``panel serve app/app.py --args --study RESULT.zarr --interface-model FILE.toml``: the Study tab browses
# that study, the Interface tab offers that model file
parser = argparse.ArgumentParser(add_help=False)
parser.add_argument("--study", default=None)
parser.add_argument("--interface-model", default=None)
options, _unknown = parser.parse_known_args(sys.argv[1:])
study = StudyScene(options.study, tasks=session.tasks)
interface = InterfaceScene(
    options.interface_model, tasks=session.tasks, executor=session.executor, dispatch=session.dispatch
)
disk = DiskScene(tasks=session.tasks, executor=session.executor, dispatch=session.dispatch)
for scene in (interface, disk):
    pn.state.on_session_destroyed(lambda _context, s=scene: s.close())
# the address: the session's settings, or a tab of its own with its settings (``?tab=interface&...``)
args, tab, problems = apply_tab_address(pn.state.session_args or {}, [interface, disk, study])
session.start(session.apply_query(args) + problems)
extra = (
    ("Interface", lambda export_card: interface_tab(interface, export_card), interface),
    ("Bladed disk", lambda export_card: disk_tab(disk, export_card), disk),
    ("Study", lambda export_card: study_tab(study, export_card), study),
)
build_page(session, pn.state.location, extra, tab).servable(title="fretwear dashboard")
