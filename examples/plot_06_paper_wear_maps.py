"""
The paper's wear maps and pseudo-FRFs (Fig. 7-9, 13)
====================================================

Wear ``w / u0`` over frequency and cycles at 6, 10 and 14 N (paper Fig. 7), the pseudo-FRFs these maps
give (the amplitude of mass 1 read at a fixed cycle count across frequencies: Fig. 8 at 6 N with the
stuck and open FRFs, Fig. 9 at several cycle counts) and the half peak-to-peak relative displacement
over the same grid (Fig. 13). The maps are the exact answer (``method="auto"``: Archard's law with no
slow-time error on the exact event-driven dynamics, read off the sliding tables), where the paper has
stepping on DLFT. As the contact wears, its normal load ``k_n (u0 - w)`` relaxes and the response
moves from the stuck FRF towards the open one. A 21 x 31 grid keeps the build fast;
``fretwear figures`` draws 41 x 60.
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

levels = (6.0, 10.0, 14.0)  # N
models = {fex: fw.paper_model(fex=fex) for fex in levels}
f = np.linspace(0.3, 1.3, 21)  # Hz
cycles = np.concatenate([[0.0], np.logspace(1, 5, 30)])
maps = {fex: fw.wear_map(m, f, cycles, kw=1e-11, workers=1) for fex, m in models.items()}
print({f"{fex:g} N": wm.label for fex, wm in maps.items()})

fig, axes = plt.subplots(1, 3, figsize=(9, 3), sharey=True, layout="constrained")
for ax, (letter, (fex, wm)) in zip(axes, zip("abc", maps.items(), strict=True), strict=True):
    mesh = ax.pcolormesh(wm.frequency, wm.cycles[1:], wm.wear_fraction[:, 1:, 0].T, vmin=0, vmax=1)
    ax.set(yscale="log", xlabel="frequency (Hz)", title=f"Fig. 7{letter}: {fex:g} N")
axes[0].set_ylabel("cycles $N$")
fig.colorbar(mesh, ax=axes, label="$w / u_0$")

# %%
# Fig. 8: at 6 N, the pseudo-FRF of the new contact (``N = 0``) follows the stuck FRF; worn, the
# contact slips and the response rises towards the open FRF.

f_fine = np.linspace(0.3, 1.3, 81)
stuck = np.abs(fw.linear_frf(models[6.0], 2 * np.pi * f_fine, state="stuck"))[:, 0]
free = np.abs(fw.linear_frf(models[6.0], 2 * np.pi * f_fine, state="open"))[:, 0]
pseudo = maps[6.0].pseudo_frf([0.0, 3e4])[:, :, 0]  # (cycle counts, frequencies)

fig, ax = plt.subplots(figsize=(6, 3.5))
ax.semilogy(f_fine, stuck, "k--", lw=0.8, label="linear, stuck")
ax.semilogy(f_fine, free, "k:", lw=0.8, label="linear, open")
ax.semilogy(f, pseudo[0], "o-", ms=3, label="nonlinear, $N$ = 0")
ax.semilogy(f, pseudo[1], "s-", ms=3, label="nonlinear, $N$ = 3e4")
ax.set(xlabel="frequency (Hz)", ylabel="$|x_1|$, first harmonic (m)", title="Fig. 8: pseudo-FRFs, 6 N")
ax.legend(fontsize=8)
fig.tight_layout()

# %%
# Fig. 9: the pseudo-FRFs at five cycle counts, for each level.

snapshots = (0.0, 1e3, 1e4, 3e4, 1e5)
fig, axes = plt.subplots(1, 3, figsize=(9, 3), sharey=True)
for ax, (letter, (fex, wm)) in zip(axes, zip("abc", maps.items(), strict=True), strict=True):
    for n, amplitude in zip(snapshots, wm.pseudo_frf(snapshots)[:, :, 0], strict=True):
        ax.semilogy(f, amplitude, lw=1, label=f"$N$ = {n:.0e}" if n else "$N$ = 0")
    ax.set(xlabel="frequency (Hz)", title=f"Fig. 9{letter}: {fex:g} N")
axes[0].set_ylabel("$|x_1|$ (m)")
axes[-1].legend(fontsize=7)
fig.tight_layout()

# %%
# Fig. 13: the half peak-to-peak relative displacement of the contact over the 10 N map (log scale,
# four decades): it grows as the contact wears and starts to slip.

wm = maps[10.0]
z = np.log10(np.maximum(wm.relative_half_peak_to_peak[:, 1:, 0].T, 1e-30))
top = z.max()
fig, ax = plt.subplots(figsize=(6, 3.5))
mesh = ax.pcolormesh(wm.frequency, wm.cycles[1:], z, vmin=top - 4, vmax=top, cmap="magma")
ax.set(yscale="log", xlabel="frequency (Hz)", ylabel="cycles $N$",
       title=f"Fig. 13: relative displacement, {wm.label}, 10 N")  # fmt: skip
fig.colorbar(mesh, ax=ax, label="log$_{10}$ $|x_1 - x_2|$ (m)")
fig.tight_layout()
