"""What a change on the wear-map scene reuses, and that every reuse is keyed by what it depends on.

Sessions run inline on small grids with a fresh cache (as ``test_state.py``); the oracle of each reuse
is the same result computed from scratch in a fresh session (or the library called directly).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the dashboard package lives at the repository root, beside fretwear
    sys.path.insert(0, str(ROOT))

import fretwear  # noqa: E402
from app.backend import Backend, Failure, ResultCache  # noqa: E402
from app.session import Session  # noqa: E402
from app.state import EXACT, Controls  # noqa: E402

SMALL = {"n_frequencies": 9, "n_cycles": 12, "harmonics": 3, "fmin": 0.4, "fmax": 1.2}


def wearmap_session(cache: ResultCache | None = None, **changes) -> Session:
    session = Session(controls=Controls(**{**SMALL, **changes}), backend=Backend(workers=2, chunks=3),
                      cache=ResultCache() if cache is None else cache)  # fmt: skip
    session.scene = "wearmap"
    return session


def shown_pair(session: Session):
    """The map's history at the selected row and the exact history drawn beside it."""
    scene = session.current
    wm = scene.results["wear_map"]
    row = int(np.argmin(np.abs(wm.frequency - session.frequency)))
    return wm.histories[row], scene.results[EXACT]


def test_the_exact_history_beside_the_exact_map_is_computed_once():
    """Slow moment: on the exact map, the history at the selected row was computed twice per change
    of k_w (the map's lazy row and the reference task, the same call)."""
    session = wearmap_session()
    row, exact = shown_pair(session)
    assert row is exact and row.method == "exact" and row.dynamics == "shooting"
    session.controls.kw = 3e-11
    row, exact = shown_pair(session)
    assert row is exact and exact.kw == 3e-11  # a new k_w: a new history, still shared


def test_every_parameter_of_the_shared_history_is_in_its_key():
    """A change of each parameter the exact history depends on (the model's F_ex, mu, F_N, k_w, the
    horizon, the frequency) gives a new history, shared again by the map's row and the reference."""
    session = wearmap_session()
    seen = [shown_pair(session)[0]]
    changes = [("fex", 12.0), ("mu", 0.9), ("normal_load", 11.0), ("kw", 2e-11), ("horizon", 5e4)]
    for name, value in changes:
        setattr(session.controls, name, value)
        row, exact = shown_pair(session)
        assert row is exact and all(row is not old for old in seen), name
        seen.append(row)
    session.frequency = float(session.current.results["wear_map"].frequency[2])
    row, exact = shown_pair(session)
    assert row is exact and all(row is not old for old in seen)
    assert row.frequency == pytest.approx(session.frequency) and row.kw == 2e-11 and row.cycles[-1] <= 5e4


def test_the_shared_exact_history_is_the_one_computed_alone():
    session = wearmap_session(kw=2e-11)
    row, _ = shown_pair(session)
    model = fretwear.paper_model(fex=10.0, mu=1.0, normal_load=10.0)
    alone = fretwear.wear_history(model, 2 * np.pi * row.frequency, "exact", kw=2e-11, cycles=1e5,
                                  dynamics="shooting")  # fmt: skip
    np.testing.assert_allclose(row.cycles, alone.cycles, rtol=1e-12)
    np.testing.assert_allclose(row.wear, alone.wear, rtol=1e-12, atol=0)


def test_a_failed_history_task_is_not_a_row_of_the_map():
    """A failure cached under a row's history key (its task failed) makes the row compute as before."""
    session = wearmap_session()
    s = session.controls.settings()
    wm = session.current.results["wear_map"]
    row = len(wm.frequency) - 1  # not the selected row: not built yet
    key = session.tasks._history_key(s, wm.frequency[row], "exact", (("dynamics", "shooting"),))
    session.cache.put(key, Failure("RuntimeError: a stand-in failure", "a stand-in failure"))
    history = wm.histories[row]
    assert isinstance(history, fretwear.WearHistory) and history.frequency == wm.frequency[row]


def _dlft_map(backend: Backend, kw: float, harmonics: int = 3, fex: float = 10.0):
    from app.backend import Grid, ModelSpec

    options = (("dynamics", "dlft"), ("harmonics", harmonics))
    return backend.wear_map(ModelSpec(fex, 1.0, 10.0), Grid(0.4, 1.2, 9), 1e5, 12, "exact", kw, options)


def _same_map(got, want) -> None:
    assert got.label == want.label
    for name in ("frequency", "cycles", "wear", "amplitude", "half_peak_to_peak"):
        w = getattr(want, name)
        np.testing.assert_allclose(getattr(got, name), w, rtol=1e-13, atol=1e-13 * np.abs(w).max(),
                                   err_msg=name)  # fmt: skip
    assert [h.status for h in got.histories] == [h.status for h in want.histories]


def test_a_new_k_w_on_the_exact_dlft_map_rescales_the_histories_that_ended_within_the_horizon():
    """Slow moment: every change of k_w on the DLFT dynamics ran the load walk of every frequency again;
    the records of the exact load path are placed in wear, so a history that ended (worn through, or
    stuck) within the horizon is the same at another k_w, its cycle counts scaled."""
    backend = Backend(workers=2, chunks=3)
    first = _dlft_map(backend, 1e-11)
    assert {h.status for h in first.histories} == {"worn", "stuck"} and backend.calls["wear_map"] == 3
    again = _dlft_map(backend, 2e-11)
    assert backend.calls["wear_map"] == 3  # nothing computed: each worn end scaled stays within 1e5
    _same_map(again, _dlft_map(Backend(workers=2, chunks=3), 2e-11))
    slower = _dlft_map(backend, 1e-14)  # scaled ends past the horizon: those frequencies run again
    assert backend.calls["wear_map"] == 6 and "horizon" in {h.status for h in slower.histories}
    _same_map(slower, _dlft_map(Backend(workers=2, chunks=3), 1e-14))


def test_the_histories_reused_across_k_w_are_keyed_by_everything_else():
    backend = Backend(workers=2, chunks=3)
    _dlft_map(backend, 1e-11)
    for change in ({"harmonics": 5}, {"fex": 8.0}):
        got = _dlft_map(backend, 2e-11, **change)
        _same_map(got, _dlft_map(Backend(workers=2, chunks=3), 2e-11, **change))
    assert backend.calls["wear_map"] == 9  # each change computed its map
