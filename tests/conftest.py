"""Marker handling shared by the test suite (markers are declared in pyproject.toml).

``slow``: long numerical studies; they run by default and in CI, and
``-m "not slow"`` leaves them out for a quick local run.
``browser``: tests that drive Debian's Chromium through Playwright; they run
with the README's test command and are skipped, with the reason, when
Playwright or /usr/bin/chromium is missing (``.ci/run`` installs both).
"""

import importlib.util
import os
import tempfile
from pathlib import Path

import numpy as np
import pytest

# One BLAS thread per process: the tests, the dashboard server they start and the kernel warm-up share
# two cores, and OpenBLAS threads that wait for a busy core slow a 350-unknown solve 25-fold (measured).
# (Read when a BLAS library loads: SciPy's, which the compiled kernels call, and every subprocess's.)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
CHROMIUM = Path("/usr/bin/chromium")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Skip ``browser`` tests when Playwright or Debian's chromium is missing."""
    if importlib.util.find_spec("playwright") is None:
        reason = "browser test: Playwright is not installed (pip install playwright)"
    elif not CHROMIUM.exists():
        reason = f"browser test: {CHROMIUM} is missing (apt-get install chromium)"
    else:
        return
    skip = pytest.mark.skip(reason=reason)
    for item in items:
        if "browser" in item.keywords:
            item.add_marker(skip)


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--slow",
        action="store_true",
        help="property-based tests with thousands of draws (hypothesis profile 'thorough')",
    )


def pytest_configure(config: pytest.Config) -> None:
    """Hypothesis profiles: a short default run, thousands of draws with --slow; the sliding tables on
    disk in a directory of this run (the tests start without them and leave the user's cache alone)."""
    from hypothesis import HealthCheck, settings

    os.environ["FRETWEAR_CACHE_DIR"] = tempfile.mkdtemp(prefix="fretwear-test-cache-")

    common = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=False)
    settings.register_profile("quick", max_examples=12, **common)
    settings.register_profile("thorough", max_examples=2000, **common)
    settings.load_profile("thorough" if config.getoption("--slow") else "quick")


def pytest_sessionstart(session: pytest.Session) -> None:
    """On a cold Numba cache (a fresh clone), compile the kernels in two processes at once first.

    The tests would compile them one after another as they first need them; two processes on two
    cores take about half of that (:func:`fretwear.compile.warm_in_processes`).
    """
    import fretwear.compile as compiled

    if not compiled.pending():
        return
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None:
        reporter.write_line("compiling numerical kernels in two processes (first run only, a few minutes)")
    compiled.warm_in_processes(env={**os.environ, "FRETWEAR_CACHE_DIR": ""})  # no sliding tables left


@pytest.fixture(scope="session")
def small_cylinder():
    """The cylinder-on-flat benchmark on a coarse mesh (5 contact pairs): the reduction tests' model."""
    from fretwear import cylinder_on_flat

    return cylinder_on_flat(contact_nodes=5, growth=1.6, pad_height=0.004, pad_half_width=0.004,
                            flat_half_width=0.006, flat_depth=0.004)  # fmt: skip


@pytest.fixture(scope="session")
def assert_linear():
    """``check(sol, model, omega, extra)``: the periodic solution ``sol`` is the linear structure with the
    stiffness ``K + extra`` (N/m) under the model's forcing at ``omega`` (rad/s): its first harmonic to 1e-10
    of the largest amplitude, every other harmonic zero to the same bound (stuck and sliding limits)."""

    def check(sol, model, omega: float, extra) -> None:
        D = model.K + extra - omega**2 * model.M + 1j * omega * model.C
        U = np.linalg.solve(D, model.force_cos - 1j * model.force_sin)
        h, scale = sol.dof_harmonics, np.abs(U).max()
        assert np.abs(h[:, 1] - U.real).max() <= 1e-10 * scale
        assert np.abs(h[:, 2] + U.imag).max() <= 1e-10 * scale
        assert np.abs(h[:, 3:]).max() <= 1e-10 * scale

    return check
