"""
A contact interface's wear scar
===============================

The cylinder-on-flat fretting test (2-D plane strain, steel on steel, ``P = 200 N/mm``, ``mu = 0.6``) on a
small mesh (16 contact node pairs, ``Nh = 3``), in partial slip (``Q0 / (mu P) = 0.5``): Archard's law at
every node pair wears the slip annulus only, the worn depth opens the local gap and the pressure moves
into the stick zone (the stick zone stays unworn). ``fretwear interface`` runs the same on 32 pairs.
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

model = fw.cylinder_on_flat(contact_nodes=16, q_ratio=0.5)
hist = fw.wear_history(model, 2 * np.pi * 50.0, kw=1e-14, cycles=3e5, harmonics=3)
print(f"{len(hist.cycles)} records to N = {hist.cycles[-1]:.3g}, {hist.solves} periodic solves")

fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6, 5))
x = hist.position * 1e3
for k in np.unique(np.linspace(0, len(hist.cycles) - 1, 4).astype(int)):
    label = f"N = {hist.cycles[k]:.3g}"
    top.plot(x, hist.wear[k] * 1e6, "o-", ms=3, label=label)
    bottom.plot(x, hist.pressure[k] / 1e6, "o-", ms=3, label=label)
top.set(ylabel="worn depth $w$ (µm)", title="cylinder on flat, partial slip")
bottom.set(xlabel="position $x$ (mm)", ylabel="pressure $p$ (MPa)")
top.legend(fontsize=8)
fig.tight_layout()

# %%
# In a notebook, the history is also an ``xarray.Dataset`` (``w`` per ``cycles`` and ``pair``, with the
# pairs' ``position``, units and long names):

hist.to_xarray()
