"""The parameter table agrees with the library's own bounds where both exist."""

from fretwear.interface.fe import MAX_CONTACT_NODES
from fretwear.parameters import PARAMETERS


def test_contact_nodes_bound_is_the_interface_builders():
    assert PARAMETERS["contact_nodes"].high == MAX_CONTACT_NODES


def test_wear_coefficients_carry_their_laws_units():
    """Lumped contacts: dw/dN = K_w F_N s (1/N); interfaces: dw/dN = K_w p s (1/Pa)."""
    assert PARAMETERS["kw"].unit == "1/N" and PARAMETERS["interface_kw"].unit == "1/Pa"
