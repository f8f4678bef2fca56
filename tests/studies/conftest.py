"""Fixtures shared by the study tests."""

from pathlib import Path

import pytest


@pytest.fixture(scope="module")
def spec_path(request, tmp_path_factory) -> Path:
    """The test module's ``SPEC`` (a study spec, TOML) written to a file."""
    path = tmp_path_factory.mktemp("spec") / "study.toml"
    path.write_text(request.module.SPEC)
    return path


@pytest.fixture
def refused(tmp_path, capsys):
    """``refused(text, key) -> message``: the spec ``text`` makes ``fretwear study`` exit 2 with one line
    naming ``key``, before it writes anything; the line is returned."""
    from fretwear import cli
    from fretwear.cli.shared import EXIT_USAGE

    def run(text: str, key: str) -> str:
        path, out = tmp_path / "bad.toml", tmp_path / "never.zarr"
        path.write_text(text)
        assert cli.main(["study", str(path), "--out", str(out)]) == EXIT_USAGE
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith(f"fretwear study: error: {key}: "), err
        assert not out.exists()
        return err[0]

    return run
