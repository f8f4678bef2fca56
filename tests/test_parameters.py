"""The one parameter table (:mod:`fretwear.parameters`) is what the dashboard, the CLI and the study spec use:
each number's valid range and default are written there only."""

import argparse
import re

import pytest

from fretwear.cli import build_parser
from fretwear.figures.record import SETTINGS_KEYS
from fretwear.interface.fe import MAX_CONTACT_NODES
from fretwear.parameters import CONTROLS, PARAMETERS
from fretwear.studies import spec


def test_contact_nodes_bound_is_the_interface_builders():
    assert PARAMETERS["contact_nodes"].high == MAX_CONTACT_NODES


def test_wear_coefficients_carry_their_laws_units():
    """Lumped contacts: dw/dN = K_w F_N s (1/N); interfaces: dw/dN = K_w p s (1/Pa)."""
    assert PARAMETERS["kw"].unit == "1/N" and PARAMETERS["interface_kw"].unit == "1/Pa"


def _options() -> list[tuple[str, argparse.Action]]:
    """(command, action) of every option of every ``fretwear`` command."""
    parser = build_parser()
    (commands,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return [(name, action) for name, sub in commands.choices.items() for action in sub._actions]


def _numeric(action: argparse.Action) -> bool:
    """Whether the option takes a number: typed, or with a numeric default (a flag's bool is none)."""
    if action.nargs == 0 or action.choices is not None:
        return False
    default = action.default
    number = isinstance(default, (int, float)) and not isinstance(default, bool)
    return number or (action.type is not None and action.type is not str)


NUMERIC = [(command, action) for command, action in _options() if _numeric(action)]


def test_the_cli_has_numeric_options_to_check():
    assert len(NUMERIC) > 50 and {c for c, _ in NUMERIC} >= {"frf", "wear", "map", "interface", "study"}


@pytest.mark.parametrize(
    ("command", "action"), NUMERIC, ids=[f"{c} {a.option_strings[0]}" for c, a in NUMERIC]
)
def test_every_numeric_cli_option_takes_its_flag_range_and_default_from_the_table(command, action):
    param = getattr(action.type, "parameter", None)
    assert param is not None, f"{command} {action.option_strings}: its type is not the table's"
    row = PARAMETERS[param.name]
    assert row.option in action.option_strings
    # the parser's range is the table's (no command widens or narrows it)
    assert param == row, f"{command} {row.option}: [{param.low}, {param.high}] is not the table's"
    if action.default is not None:
        assert action.default == row.default_for(command), f"{command} {row.option}"


def test_the_dashboards_controls_are_the_tables():
    from app.state import CONTROL_KEYS, NUMBERS, Controls

    c = Controls(preset="custom")
    numbers = {n for n, p in Controls.param.objects().items() if type(p).__name__ == "Number"}
    assert numbers == set(NUMBERS) == set(CONTROLS)
    for name, row in CONTROLS.items():
        control = Controls.param[name]
        assert getattr(c, name) == control.default == row.default
        assert control.softbounds == row.soft_bounds and CONTROL_KEYS[name] == row.name
        assert row.low < row.high and row.slider is not None
        low, high = row.soft_bounds
        assert row.valid(low) and row.valid(high), f"{name}: its slider leaves the valid range"
        message = f"{row.label} must be {row.range_text(whole=True)}, got "
        for value, ok in ((row.low, not row.low_strict), (row.high, not row.high_strict)):
            c.param.update(**{name: value})
            assert any(m.startswith(message) for m in c.problems()) is not ok, (name, value)
        c.param.update(**{name: row.high * 2 + 1})
        assert any(m.startswith(message) for m in c.problems())
        c.param.update(**{name: row.default})


def test_the_sidebars_numbers_are_the_tables():
    from app.glossary import TERMS

    for name, row in CONTROLS.items():
        assert row.html and (row.glossary is None or row.glossary in TERMS), name
        start, end, step = row.slider
        assert start < end and 0 < step <= end - start, name
        assert not row.integer or all(float(v).is_integer() for v in row.slider), name


def test_the_settings_file_keys_are_the_tables():
    for name, row in CONTROLS.items():
        kind, meaning = SETTINGS_KEYS[row.name]
        assert kind is (int if row.integer else float) and meaning.endswith(f"({row.unit or '-'})"), name


def test_the_study_spec_takes_its_bounds_units_and_defaults_from_the_table():
    numbers = [p for p in spec.PARAMETERS.values() if p.kind is not str]
    assert len(numbers) >= 10
    for p in numbers:
        row = PARAMETERS[p.table]
        assert p.unit == (row.unit or "-") and p.kind is (int if row.integer else float)
        inside = row.default if row.default is not None else row.high
        assert p.check("x", inside) == inside
        for outside in (row.high * 2 + 1, row.low - 1):
            with pytest.raises(spec.SpecError, match=re.escape(f"x: must be {row.range_text()}, got")):
                p.check("x", outside)
    for name, value in spec.PAPER_DEFAULTS.items():
        assert value == PARAMETERS[spec.PARAMETERS[name].table].default
    assert spec.DEFAULTS["kw"] == PARAMETERS["kw"].default
    assert spec.FRF_HARMONICS == PARAMETERS["harmonics"].default_for("study")


@pytest.mark.parametrize("name", ["mu", "fn", "cycles", "fmax", "nf", "ncycles"])
def test_a_typed_value_is_valid_in_the_app_exactly_where_the_cli_and_the_spec_take_it(name):
    """The ranges that differed (app f <= 20 Hz, horizon 10 to 1e9 whole, mu and F_N > 0 in the app only,
    map grids of 3 and 4 in the app, 1 and 2 in the CLI) are one range now."""
    from app.state import Controls

    row = PARAMETERS[name]
    probes = {row.low, row.high, row.low + 1, row.high + 1, 0.5, 2.5, 20.5, 1e9 + 1, 3, 2, 1}
    cli = {a.option_strings[0]: a.type for c, a in NUMERIC if a.type.parameter.name == name}
    study = [p for p in spec.PARAMETERS.values() if p.table == name]
    for value in sorted(probes):
        c = Controls(preset="custom", **{row.control: value}) if row.control else None
        message = f"{row.label} must be {row.range_text(whole=True)}, got "
        app_ok = None if c is None else not any(m.startswith(message) for m in c.problems())
        for flag, convert in cli.items():
            try:
                convert(repr(value))
                cli_ok = True
            except argparse.ArgumentTypeError:
                cli_ok = False
            assert app_ok in (None, cli_ok), (name, value, flag)
        for p in study:
            try:
                p.check("x", int(value) if p.kind is int and float(value).is_integer() else value)
                spec_ok = True
            except spec.SpecError:
                spec_ok = False
            assert app_ok in (None, spec_ok) and spec_ok == row.valid(value), (name, value)
