"""Fixtures shared by the study tests."""

from pathlib import Path

import pytest


@pytest.fixture(scope="module")
def spec_path(request, tmp_path_factory) -> Path:
    """The test module's ``SPEC`` (a study spec, TOML) written to a file."""
    path = tmp_path_factory.mktemp("spec") / "study.toml"
    path.write_text(request.module.SPEC)
    return path
