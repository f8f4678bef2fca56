"""
The polynomial method's wear map (Fig. 12, 14)
==============================================

The paper's polynomial method (eq. 25-29) on DLFT at ``Nh = 3`` over the 10 N map: wear ``w / u0``
(paper Fig. 12) and the half peak-to-peak relative displacement (paper Fig. 14). fretwear's basis
saturates (degree 4), so that ``w`` stays below ``u0``. Both the truncation to 3 harmonics and the
polynomial slow time are approximations: the third panel is the map's error in ``w / u0`` against the
exact answer on the same grid (exact slow time on the exact event-driven dynamics).
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

model = fw.paper_model(fex=10.0)
f = np.linspace(0.3, 1.3, 21)  # Hz
cycles = np.concatenate([[0.0], np.logspace(1, 5, 30)])
poly = fw.wear_map(model, f, cycles, method="polynomial", kw=1e-11, harmonics=3, degree=4, workers=1)
exact = fw.wear_map(model, f, cycles, kw=1e-11, workers=1)
error = poly.wear_fraction[:, :, 0] - exact.wear_fraction[:, :, 0]
print(f"{poly.label}: largest error in w / u0 against the {exact.label} map: {np.abs(error).max():.3f}")

fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.2), sharey=True)
mesh = left.pcolormesh(f, cycles[1:], poly.wear_fraction[:, 1:, 0].T, vmin=0, vmax=1)
fig.colorbar(mesh, ax=left, label="$w / u_0$")
left.set(yscale="log", xlabel="frequency (Hz)", ylabel="cycles $N$", title="Fig. 12: polynomial, $N_h$ = 3")
bound = np.abs(error).max()
mesh = right.pcolormesh(f, cycles[1:], error[:, 1:].T, cmap="RdBu_r", vmin=-bound, vmax=bound)
fig.colorbar(mesh, ax=right, label="error in $w / u_0$")
right.set(yscale="log", xlabel="frequency (Hz)", title="polynomial minus exact")
fig.tight_layout()

# %%
# Fig. 14: the relative displacement over the polynomial map (log scale, four decades).

z = np.log10(np.maximum(poly.relative_half_peak_to_peak[:, 1:, 0].T, 1e-30))
top = z.max()
fig, ax = plt.subplots(figsize=(6, 3.5))
mesh = ax.pcolormesh(f, cycles[1:], z, vmin=top - 4, vmax=top, cmap="magma")
ax.set(yscale="log", xlabel="frequency (Hz)", ylabel="cycles $N$",
       title="Fig. 14: relative displacement, polynomial, 10 N")  # fmt: skip
fig.colorbar(mesh, ax=ax, label="log$_{10}$ $|x_1 - x_2|$ (m)")
fig.tight_layout()
