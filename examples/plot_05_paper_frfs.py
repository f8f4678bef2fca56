"""
The paper's FRFs at three forcing levels (Fig. 5-6)
===================================================

The 2-DOF example at ``F_ex`` = 6, 10 and 14 N (``mu = 1``, ``F_N = 10 N``, no wear): the first-harmonic
amplitude of mass 1 (paper Fig. 5) and the half peak-to-peak relative displacement ``x1 - x2`` of the
contact (paper Fig. 6), against the linear FRFs with the contact stuck and open. The nonlinear FRFs are
harmonic balance with DLFT at ``Nh = 7``: an approximation (its truncation error:
:doc:`/user_guide/periodic`). At 6 N the contact sticks over most of the band and the
response follows the stuck FRF; at 14 N it slips and the peak moves towards the open one.
``fretwear figures`` writes the same figures at ``Nh = 21`` on a finer grid.
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

f = np.linspace(0.3, 1.3, 41)  # Hz
levels = (6.0, 10.0, 14.0)  # N
models = {fex: fw.paper_model(fex=fex) for fex in levels}
frfs = {fex: fw.sweep(m, 2 * np.pi * f, harmonics=7) for fex, m in models.items()}  # HBM + DLFT
linear = {
    (fex, state): fw.linear_frf(models[fex], 2 * np.pi * f, state=state)
    for fex in (levels[0], levels[-1])
    for state in ("stuck", "open")
}

fig, ax = plt.subplots(figsize=(6, 3.5))
for fex, frf in frfs.items():
    ax.semilogy(f, [s.amplitude[0] for s in frf.solutions], label=f"{fex:g} N, DLFT $N_h$ = 7")
for (fex, state), u in linear.items():
    style = "k--" if state == "stuck" else "k:"
    ax.semilogy(f, np.abs(u[:, 0]), style, lw=0.8, label=f"linear {state}, {fex:g} N")
ax.set(xlabel="frequency (Hz)", ylabel="$|x_1|$, first harmonic (m)", title="Fig. 5: FRF of mass 1")
ax.legend(fontsize=7, ncol=2)
fig.tight_layout()

# %%
# The relative displacement of the contact: zero while it sticks (Fig. 6; round-off below the axis).
# The open FRF of the relative displacement is ``B u`` with the contact's relative map ``B``.

B = models[10.0].relative_map()[0]
fig, ax = plt.subplots(figsize=(6, 3.5))
for fex, frf in frfs.items():
    rel = [s.relative_half_peak_to_peak[0] for s in frf.solutions]
    ax.semilogy(f, rel, label=f"{fex:g} N, DLFT $N_h$ = 7")
for fex in (levels[0], levels[-1]):
    ax.semilogy(f, np.abs(linear[fex, "open"] @ B), "k:", lw=0.8, label=f"linear open, {fex:g} N")
ax.set_ylim(bottom=1e-3)
ax.set(xlabel="frequency (Hz)", ylabel="$x_1 - x_2$, half peak-to-peak (m)",
       title="Fig. 6: FRF of the relative displacement")  # fmt: skip
ax.legend(fontsize=7)
fig.tight_layout()
