"""Tests of app.page without a browser: the zip of every export of a scene."""

import io
import json
import zipfile

import pytest

from app.page import ExportSettings, bundle


class Tab:
    """A scene with one computed figure, one not computed yet, and one data set."""

    key = "tab"
    figure_names = ("ready", "pending")
    dataset_names = ("table",)

    def __init__(self, computed: bool = True):
        self.computed, self.asked = computed, []

    def filename(self, name, fmt):
        return f"fretwear_tab_{name}.{fmt}"

    def export_figure(self, name, fmt, options):
        self.asked.append((fmt, options.dpi))
        if name == "pending" or not self.computed:
            raise ValueError("nothing to export yet: not computed")
        return f"{name}.{fmt}".encode()

    def export_csv(self, name):
        if not self.computed:
            raise ValueError("nothing to export yet: not computed")
        return "# k_w = 1e-11 1/N\nf_hz\n0.7\n"

    def csv_header(self):
        return "# tab parameters\n"


def unzip(data: bytes) -> dict[str, bytes]:
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        return {n: archive.read(n) for n in archive.namelist()}


def test_the_zip_holds_every_export_the_settings_and_what_is_missing():
    settings = ExportSettings(dpi="5000")  # a resolution only PNG reads
    files = unzip(bundle(Tab(), settings.options, view=lambda: {"kw": 1e-11, "scene": "wearmap"}))
    assert files["fretwear_tab_ready.svg"] == b"ready.svg" and files["fretwear_tab_ready.pdf"] == b"ready.pdf"
    assert "fretwear_tab_ready.png" not in files  # dpi 5000: refused, and said so
    assert files["fretwear_tab_table.csv"].startswith(b"# k_w")
    assert json.loads(files["settings.json"])["kw"] == 1e-11
    missing = files["missing.txt"].decode()
    assert "fretwear_tab_ready.png: dpi must be a whole number in [50, 600]" in missing
    assert "fretwear_tab_pending.svg: nothing to export yet" in missing
    # a tab with settings of its own: its parameters instead of a settings file
    files = unzip(bundle(Tab(), ExportSettings().options))
    assert files["parameters.txt"] == b"# tab parameters\n" and "settings.json" not in files
    assert files["fretwear_tab_ready.png"] == b"ready.png"


def test_a_zip_of_nothing_is_an_error_not_an_empty_file():
    with pytest.raises(ValueError, match="nothing to export yet: fretwear_tab_ready.png: nothing to export"):
        bundle(Tab(computed=False), ExportSettings().options)


def test_a_tab_of_its_own_keeps_its_view_in_the_address():
    """Defect: on the Interface and Study tabs the address stayed empty: a link could not hold them."""
    from app.backend import Backend, ResultCache
    from app.page import apply_tab_address
    from app.scenes.disk import DiskScene
    from app.scenes.interface import PAPER, InterfaceScene
    from app.state import Tasks

    def scenes():
        tasks = Tasks(Backend(), ResultCache())
        return [InterfaceScene(tasks=tasks), DiskScene(tasks=tasks)]

    shown = scenes()[0]
    shown.param.update(model=PAPER, harmonics=7)  # nothing computes: the tab is not shown
    query = {"tab": [b"interface"], "fex": [b"12"], **{k: [v.encode()] for k, v in shown.address().items()}}
    assert shown.address()["interface.model"] == PAPER and shown.address()["interface.frequency"] == "0.7"
    opened = scenes()
    rest, tab, problems = apply_tab_address(query, opened)
    assert (tab, problems, rest) == ("interface", [], {"fex": [b"12"]})  # the session's keys go on
    assert opened[0].settings() == shown.settings()
    # bad parts are named, the good ones kept
    opened = scenes()
    query = {"tab": [b"disk"], "disk.engine_order": [b"5"], "disk.frequency": [b"abc"],
             "interface.kw": [b"1"], "disk.colour": [b"red"]}  # fmt: skip
    rest, tab, problems = apply_tab_address(query, opened)
    assert tab == "disk" and opened[1].engine_order == 5 and opened[1].typed == {"frequency": "abc"}
    assert any("unknown setting 'disk.colour'" in p for p in problems)
    assert "address: interface.kw belongs to another tab than 'disk'" in problems
    _rest, tab, problems = apply_tab_address({"tab": [b"nowhere"]}, scenes())
    assert tab is None and problems == ["address: tab must be one of interface, disk, got 'nowhere'"]
