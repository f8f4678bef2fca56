"""``--size`` and ``--dpi`` of the figure files of ``fretwear map`` and ``fretwear figures`` (issue 26)."""

import pytest

from fretwear import cli, figures

MAP = ["map", "--nf", "3", "--ncycles", "4", "--cycles", "1e4"]


def png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def test_map_figure_at_a_named_size_and_the_dashboards_dpi(tmp_path, capsys):
    """Defect: ``fretwear map --out x.png`` wrote 120 dpi where the dashboard writes 150; no size presets."""
    assert cli.main([*MAP, "--out", str(tmp_path / "own.png")]) == 0
    assert png_size((tmp_path / "own.png").read_bytes()) == (7 * 150, 4 * 150)
    assert cli.main([*MAP, "--size", "column", "--out", str(tmp_path / "column.png")]) == 0
    assert png_size((tmp_path / "column.png").read_bytes()) == (525, 375)
    argv = [*MAP, "--size", "slide", "--height", "5", "--dpi", "50", "--out", str(tmp_path / "slide.pdf")]
    assert cli.main(argv) == 0
    pdf = (tmp_path / "slide.pdf").read_bytes().decode("latin-1")
    assert "/Title (Wear map" in pdf and "/Creator (fretwear " in pdf
    assert "/MediaBox [ 0 0 720 360 ]" in pdf  # 10 x 5 in
    capsys.readouterr()
    assert cli.main([*MAP, "--size", "poster", "--out", str(tmp_path / "x.png")]) == 2
    assert "--size: invalid choice: 'poster'" in capsys.readouterr().err


@pytest.mark.parametrize("size", list(figures.SIZES))
def test_figures_command_takes_the_size_presets(size):
    assert list(cli.shared.SIZES) == list(figures.SIZES)  # the CLI's names without importing the plotting
    args = cli.build_parser().parse_args(["figures", "--out", "f", "--size", size, "--fontsize", "9"])
    options = cli.shared.export_options(args)
    width, height, _ = figures.SIZES[size]
    assert (options.width, options.height, options.fontsize, options.dpi) == (width, height, 9.0, 150)
