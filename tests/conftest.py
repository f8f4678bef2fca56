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
