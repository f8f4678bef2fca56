"""Fixtures of the dashboard's browser tests."""

import pytest


@pytest.fixture(scope="module")
def browser():
    """One headless Debian chromium per test module (Playwright, no browser download)."""
    from playwright.sync_api import sync_playwright
    from test_browser import CHROMIUM, CHROMIUM_ARGS

    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        yield chromium
        chromium.close()
