"""
The paper's FRF and wear map
============================

The 2-DOF example of Salles et al. (section 2.1, eq. 30): two unit masses, a friction contact between
them whose normal load ``F_N = k_n (u0 - w)`` relaxes as the contact wears. At ``F_ex = 10 N`` the
nonlinear FRF lies between the stuck linear FRF (1 Hz) and the one with the contact open (0.5 Hz)
(paper Fig. 5 and 8); the wear map ``w / u0`` over frequency and cycles (paper Fig. 7b) is the exact
answer: Archard's law with no slow-time error on the exact event-driven dynamics. A small grid keeps
the build fast; ``fretwear figures`` draws the paper's full figure set.
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

model = fw.paper_model(fex=10.0, mu=1.0, normal_load=10.0)
f = np.linspace(0.3, 1.3, 41)  # Hz
frf = fw.sweep(model, 2 * np.pi * f, harmonics=7)  # HBM + DLFT, no wear
stuck = np.abs(fw.linear_frf(model, 2 * np.pi * f, state="stuck"))[:, 0]
free = np.abs(fw.linear_frf(model, 2 * np.pi * f, state="open"))[:, 0]

fig, ax = plt.subplots(figsize=(6, 3.5))
ax.semilogy(f, stuck, "k--", lw=1, label="linear, stuck")
ax.semilogy(f, free, "k:", lw=1, label="linear, open")
ax.semilogy(f, [s.amplitude[0] for s in frf.solutions], "C0", label="nonlinear, no wear ($N_h$ = 7)")
ax.set(xlabel="frequency (Hz)", ylabel="$|x_1|$, first harmonic (m)", title="FRF, $F_{ex}$ = 10 N")
ax.legend()
fig.tight_layout()

# %%
# The wear map: the exact answer at every frequency and cycle count, read off the sliding tables.

fmap = np.linspace(0.4, 1.2, 17)
cycles = np.logspace(2, 5, 40)
wmap = fw.wear_map(model, fmap, cycles, kw=1e-11)
print(wmap.label)

fig, ax = plt.subplots(figsize=(6, 3.5))
mesh = ax.pcolormesh(wmap.frequency, wmap.cycles, wmap.wear[:, :, 0].T / 1e-6, shading="nearest")
ax.set(yscale="log", xlabel="frequency (Hz)", ylabel="cycles $N$", title=f"$w / u_0$: {wmap.label}")
fig.colorbar(mesh, ax=ax, label="$w / u_0$")
fig.tight_layout()
