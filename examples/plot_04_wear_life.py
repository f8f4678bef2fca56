"""
A wear-life study
=================

The cycles to half wear of the paper model at 0.7 Hz when the friction coefficient and the forcing are
uncertain: ``mu`` uniform in [0.4, 1.0], ``F_ex`` normal (10 N, 1 N), as in the shipped study
``fretwear/data/wear_life.toml`` (1000 draws on Dask: ``fretwear study``). Here 40 draws, each the exact
answer, in one process: the life is a wide distribution, and a few draws stick (no wear).
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

rng = np.random.default_rng(0)
mu = rng.uniform(0.4, 1.0, 40)
fex = rng.normal(10.0, 1.0, 40)
life = np.array(
    [
        fw.wear_history(fw.paper_model(fex=F, mu=m), 2 * np.pi * 0.7, kw=1e-11, cycles=1e5).cycles_to(0.5)
        for F, m in zip(fex, mu, strict=True)
    ]
)
worn = np.isfinite(life)
q5, q50, q95 = np.quantile(life[worn], [0.05, 0.5, 0.95])
print(f"cycles to 0.5 u0: median {q50:.0f}, 5 % {q5:.0f}, 95 % {q95:.0f}")
print(f"{np.sum(~worn)} of 40 draws stick or stay below 0.5 u0 for 1e5 cycles")

fig, (hist_ax, scatter_ax) = plt.subplots(1, 2, figsize=(7, 3))
hist_ax.hist(np.log10(life[worn]), bins=12)
hist_ax.axvline(np.log10(q50), color="k", lw=1)
hist_ax.set(xlabel="log10 cycles to 0.5 $u_0$", ylabel="draws")
scatter_ax.scatter(fex[worn] / mu[worn], life[worn], s=8)
scatter_ax.set(xscale="log", yscale="log", xlabel=r"$F_{ex} / \mu$ (N)", ylabel="cycles to 0.5 $u_0$")
fig.tight_layout()
