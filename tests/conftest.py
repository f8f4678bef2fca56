"""Marker handling shared by the test suite (markers are declared in pyproject.toml).

``slow``: long numerical studies; they run by default and in CI, and
``-m "not slow"`` leaves them out for a quick local run.
``browser``: tests that drive Chromium through Playwright; the README's test
command leaves them out, and they are skipped, with the reason, when
Playwright is not installed.
"""

import importlib.util

import pytest


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Skip ``browser`` tests when Playwright is missing."""
    if importlib.util.find_spec("playwright") is not None:
        return
    skip = pytest.mark.skip(reason="browser test: Playwright is not installed")
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
    """Hypothesis profiles: a short default run, thousands of draws with --slow."""
    from hypothesis import HealthCheck, settings

    common = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=False)
    settings.register_profile("quick", max_examples=12, **common)
    settings.register_profile("thorough", max_examples=2000, **common)
    settings.load_profile("thorough" if config.getoption("--slow") else "quick")
