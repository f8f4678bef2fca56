"""Server warm-up: the first exact wear map at the dashboard's defaults solves nothing."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the dashboard package lives at the repository root, beside fretwear
    sys.path.insert(0, str(ROOT))

from app.backend import Backend  # noqa: E402
from app.state import Controls  # noqa: E402
from app.warmup import warm_tables  # noqa: E402
from fretwear.wear import sliding  # noqa: E402


def test_warm_up_builds_the_sliding_tables_of_the_default_exact_map(tmp_path, monkeypatch):
    monkeypatch.setenv("FRETWEAR_CACHE_DIR", str(tmp_path))  # no table on disk
    monkeypatch.setattr(sliding, "_cache", {})  # nor in memory: a fresh server
    warm_tables()
    solves = []
    shoot = sliding._orbits
    monkeypatch.setattr(
        sliding, "_orbits", lambda table, at, *a, **k: solves.append(len(at)) or shoot(table, at, *a, **k)
    )
    s = Controls().settings()  # the defaults: what the first page with a wear number computes
    exact = ("exact", s.kw, (("dynamics", "shooting"),))
    wm = Backend(workers=2).wear_map(s.model, s.frequency_grid, s.horizon, s.n_cycles, *exact)
    assert solves == []  # every table came from the warm-up
    assert wm.wear.shape == (len(s.frequencies), len(s.cycles), 1) and wm.wear_fraction.max() > 0.5
    # another F_ex in range: the same tables (a forcing up to 4 times larger needs no solve)
    other = Backend().wear_map(_forcing_times(s.model, 1.5), s.frequency_grid, s.horizon, s.n_cycles, *exact)
    assert solves == [] and not (other.wear == wm.wear).all()


def _forcing_times(spec, factor):
    from dataclasses import replace

    return replace(spec, fex=spec.fex * factor)


def test_the_accuracy_ladder_of_the_defaults_is_warmed_after_the_first_page():
    """Slow moment: the Accuracy tab's first opening took 9.8 s; its default ladder is now computed by the
    warm-up in the background, and the tab opens from the cache (timing: benchmarks/bench_app.py)."""
    from app.backend import shared_backend
    from app.session import Session
    from app.warmup import warm_later

    warm_later(("accuracy",), delay=0.0).join()
    backend = shared_backend()
    before = dict(backend.calls)
    session = Session()
    session.scene = "accuracy"
    assert dict(backend.calls) == before  # nothing computed: every rung from the cache
    assert session.current.study() is not None and len(session.current.study().rungs) >= 3
