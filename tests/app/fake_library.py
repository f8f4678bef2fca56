"""Library replacements for the browser tests' server (``FRETWEAR_APP_LIBRARY=fake_library``).

The real library, except the polynomial slow-time method's wear maps: they are
the exact load path's maps with the two defects the polynomial method showed in
issue 12 at F_ex 14 N, mu 0.8, k_w 1e-10, 0.7 Hz: ``w / u0`` reaching 1.18 at
0.7 Hz (with the misfit warning), and a spurious response at ``N = 0`` (a 14 m
peak at 0.525 Hz). The dashboard must show the first (colour scale, located
note) and must not draw the second as the response without wear.
"""

import numpy as np

import fretwear

#: what the polynomial method's maps get wrong: w / u0 at 0.7 Hz, x1 at N = 0 and 0.525 Hz (m)
OVERSHOOT, SPURIOUS = 1.18, 14.0


def wear_map(model, frequencies, cycles, *, method="auto", **options):
    """:func:`fretwear.wear_map`; for ``method="polynomial"``, the exact map with the defects above."""
    if method != "polynomial":
        return fretwear.wear_map(model, frequencies, cycles, method=method, **options)
    exact = {k: v for k, v in options.items() if k in ("kw", "harmonics", "workers")}
    wm = fretwear.wear_map(model, frequencies, cycles, method="exact", **exact)
    for i, f in enumerate(wm.frequency):
        h = wm.histories[i]
        h.method = "polynomial"
        if np.isclose(f, 0.7):
            h.wear[-1, 0] = wm.wear[i, -1, 0] = OVERSHOOT * wm.u0[0]
            h.warnings.append(f"polynomial fit at {f:.4g} Hz misses its own Archard law (fake)")
        if np.isclose(f, 0.525):
            wm.amplitude[i, 0, 0] = SPURIOUS
    return wm


def replacements() -> dict:
    return {"wear_map": wear_map}
