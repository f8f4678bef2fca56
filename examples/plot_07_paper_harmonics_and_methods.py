"""
Harmonics and slow-time methods against the exact answer (Fig. 10-11)
=====================================================================

``w(N)`` at 0.7 Hz and 10 N (``K_w = 1e-11``): by stepping on DLFT with 1, 3, 7, 15 and 21 harmonics
(paper Fig. 10), and by every slow-time method (paper Fig. 11): the exact slow time and stepping on DLFT
at ``Nh = 21``, the polynomial method (saturating basis, degree 4) on DLFT at ``Nh = 3``, and the time
integration (event-driven dynamics with cycle jumps). DLFT and the polynomial method are approximations;
the dashed curve is the exact answer (exact slow time on the exact event-driven dynamics), and each
curve's error in the cycles to half wear is printed against it: on DLFT the contact wears early, by less
as ``Nh`` grows.
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

model = fw.paper_model(fex=10.0)
exact = fw.wear_history(model, 2 * np.pi * 0.7, kw=1e-11, cycles=1e5)  # the exact answer (the default)
print(f"{exact.label}: {exact.cycles_to(0.5):.0f} cycles to 0.5 u0")
by_harmonics = fw.harmonic_convergence(model, 0.7, kw=1e-11, cycles=1e5)  # stepping on DLFT
for nh, hist in by_harmonics.items():
    err = hist.error_against(exact)["cycles_to_0.5"]
    print(f"Nh = {nh}: {hist.cycles_to(0.5):.0f} cycles to 0.5 u0, {err:+.1%} against the exact answer")


def draw(histories, title):
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for label, hist in histories.items():
        ax.semilogx(hist.cycles[1:], hist.wear_fraction[1:, 0], label=label)
    ax.semilogx(exact.cycles[1:], exact.wear_fraction[1:, 0], "k--", label="exact answer")
    ax.set(xlabel="cycles $N$", ylabel="$w / u_0$", title=title)
    ax.legend(fontsize=7)
    fig.tight_layout()


draw({f"DLFT, $N_h$ = {nh}": h for nh, h in by_harmonics.items()}, "Fig. 10: harmonics, 0.7 Hz, 10 N")

# %%
# Fig. 11: the slow-time methods, each at its own settings.

methods = fw.compare_methods(model, 0.7, kw=1e-11, cycles=1e5, harmonics=21, degree=4,
                             overrides={"polynomial": {"harmonics": 3}})  # fmt: skip
for hist in methods.values():
    err = hist.error_against(exact)["cycles_to_0.5"]
    print(f"{hist.label}: {hist.cycles_to(0.5):.0f} cycles to 0.5 u0, {err:+.1%} against the exact answer")
draw({h.label: h for h in methods.values()}, "Fig. 11: slow-time methods, 0.7 Hz, 10 N")
