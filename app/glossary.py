"""The dashboard's glossary: each term's symbol (HTML) and a one-to-three-sentence definition.

The same text appears in three places: the *Glossary* tab (:func:`glossary_markdown`),
the help mark beside each control (:func:`help_mark`) and the terms of the
scenes' explanations (:func:`term`, a hover note).
"""

from __future__ import annotations

import html

__all__ = ["TERMS", "term", "help_mark", "glossary_markdown"]

#: term -> (symbol in HTML, definition); the keys are the names used in the code and the URL
TERMS: dict[str, tuple[str, str]] = {
    "F_ex": (
        "F<sub>ex</sub>",
        "Excitation amplitude (N): mass 1 is driven by Fₑₓ cos(ωt). Larger Fₑₓ makes the contact slip "
        "over more of the period.",
    ),
    "mu": (
        "μ",
        "Coulomb friction coefficient (-): the contact sticks while the friction force stays below "
        "μ Fₙ and slips at μ Fₙ.",
    ),
    "F_N": (
        "F<sub>N</sub>",
        "Normal load on the contact (N), Fₙ = kₙ (u₀ − w): the normal spring kₙ is compressed by the "
        "interference u₀, less the worn depth w. Wear relaxes it.",
    ),
    "u0": (
        "u<sub>0</sub>",
        "Initial interference of the normal spring (m), u₀ = Fₙ / kₙ: the depth the contact can wear "
        "before its normal load vanishes (w / u₀ = 1: worn through).",
    ),
    "k_w": (
        "k<sub>w</sub>",
        "Archard wear coefficient (1/N): per cycle, the worn depth grows by k_w Fₙ s, with s the "
        "distance slid. Only the product k_w N matters: doubling k_w halves the cycles to a given wear.",
    ),
    "N": (
        "N",
        "Number of vibration cycles (the slow time of wear). The cycle horizon is the largest N computed.",
    ),
    "Nh": (
        "N<sub>h</sub>",
        "Number of harmonics of the harmonic balance: the periodic response is a Fourier series up to "
        "N_h ω. More harmonics sharpen the stick-slip transitions (error about 1/N_h) and cost more.",
    ),
    "DLFT": (
        "DLFT",
        "Dynamic Lagrangian Frequency-Time method: the contact law (stick, slip, separation) is applied "
        "in the time domain, sample by sample, and the result is brought back to harmonics for the "
        "harmonic balance (HBM + DLFT).",
    ),
    "pseudo-FRF": (
        "pseudo-FRF",
        "The response over frequency after N cycles of wear, each frequency worn by its own vibration: "
        "not the response of one worn structure, since each frequency wears differently.",
    ),
    "wear map": (
        "wear map",
        "The worn depth w / u₀ over frequency and number of cycles N: where and how fast the contact "
        "wears. Click it to pick the point the other scenes show.",
    ),
    "r": (
        "r",
        "Load ratio r = Fₑₓ / (μ Fₙ): the excitation over the friction limit. Below the stick "
        "boundary the contact never slips (and never wears); far above it, it slips almost all the time.",
    ),
    "method": (
        "slow-time method",
        "How the wear is followed over N: exact (Archard's law integrated exactly along the load path: "
        "no slow-time error), stepping (adaptive steps in N), polynomial (the paper's polynomial in N, "
        "one solve, on DLFT) or time (direct time integration with cycle jumps). The default, the exact "
        "method on the exact dynamics, is the exact answer; anything else is an approximation, shown "
        "with its measured error.",
    ),
    "dynamics": (
        "dynamics",
        "The periodic response the exact and stepping methods wear along: exact (event-driven time "
        "integration, periodic by shooting: no truncation) or DLFT (harmonic balance with N_h "
        "harmonics: the paper's approximation, error about 1/N_h).",
    ),
    "tolerance": (
        "tolerance",
        "Local error allowed per step in w / u₀ by stepping and time integration; the exact and "
        "polynomial methods do not take one.",
    ),
    "stick-slip": (
        "stick / slip",
        "In one period the contact sticks (both masses move together, the friction force is below μ Fₙ) "
        "or slips (the masses slide, the friction force is ±μ Fₙ): only slipping wears.",
    ),
}


#: inline styles (the page's widgets live in shadow DOM, out of reach of a page-wide style sheet)
_TERM_STYLE = "text-decoration: underline dotted; cursor: help"
_MARK_STYLE = (
    "display: inline-block; width: 1.15em; height: 1.15em; line-height: 1.15em; border-radius: 50%; "
    "background: #0d6efd; color: white; text-align: center; font-size: 0.75em; font-weight: bold; "
    "cursor: help; margin-left: 0.35em; vertical-align: 0.1em"
)


#: the definition a ? mark opens in place
_NOTE_STYLE = (
    "display: block; font-size: 0.85em; color: #333; background: #eef4ff; padding: 2px 6px; margin: 2px 0"
)


def term(name: str, text: str | None = None) -> str:
    """``text`` (default the term's symbol) in HTML with the definition of ``name`` as a hover note."""
    symbol, definition = TERMS[name]
    shown = symbol if text is None else text
    return f'<abbr data-term="{name}" title="{html.escape(definition)}" style="{_TERM_STYLE}">{shown}</abbr>'


def help_mark(name: str) -> str:
    """A small ? mark beside a control's label: its hover note is the definition of ``name``, and from the
    keyboard (Tab to it, Enter) it opens the definition in place (a ``<details>``)."""
    _, definition = TERMS[name]
    text = html.escape(definition)
    return (
        f'<details style="display: inline"><summary data-term="{name}" title="{text}" aria-label="{text}" '
        f'style="{_MARK_STYLE}; list-style: none">?</summary>'
        f'<span style="{_NOTE_STYLE}">{text}</span></details>'
    )


def glossary_markdown() -> str:
    """The glossary as Markdown: one bold symbol and its definition per term."""
    return "\n\n".join(f"**{symbol}** ({name}): {text}" for name, (symbol, text) in TERMS.items())
