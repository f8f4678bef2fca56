"""
Exact against DLFT: cycles to half wear
=======================================

At 10 N and 0.7 Hz (the dashboard's default point) the contact wears to half its initial interference
``u0`` after about 5 000 cycles. The exact answer integrates Archard's law with no slow-time error on the
exact event-driven dynamics (shooting, no harmonic truncation). The paper's approximations (DLFT at a
finite ``Nh``, the polynomial slow time of eq. 25-29) each give their own count, and ``error_against``
measures it against the exact one. The polynomial slow time is also measured against the exact slow
time on the same DLFT dynamics (``Nh = 3``): its own error is small; the rest is the truncation's.
"""

import matplotlib.pyplot as plt
import numpy as np

import fretwear as fw

model = fw.paper_model(fex=10.0)
omega = 2 * np.pi * 0.7
exact = fw.wear_history(model, omega, kw=1e-11, cycles=2e4)  # the exact answer (the default)
runs = {
    "exact slow time on DLFT, Nh = 7": fw.wear_history(model, omega, kw=1e-11, cycles=2e4, harmonics=7),
    "exact slow time on DLFT, Nh = 21": fw.wear_history(model, omega, kw=1e-11, cycles=2e4, harmonics=21),
    "exact slow time on DLFT, Nh = 3": fw.wear_history(model, omega, kw=1e-11, cycles=2e4, harmonics=3),
    "polynomial (saturating, degree 4), Nh = 3": fw.wear_history(
        model, omega, "polynomial", kw=1e-11, cycles=2e4, harmonics=3, degree=4
    ),
}

print(f"{exact.label}: {exact.cycles_to(0.5):.0f} cycles to 0.5 u0")
for name, hist in runs.items():
    err = hist.error_against(exact)["cycles_to_0.5"]
    print(f"{name}: {hist.cycles_to(0.5):.0f} cycles to 0.5 u0, {err:+.2%} against the exact answer")
same_dynamics = runs["polynomial (saturating, degree 4), Nh = 3"].error_against(
    runs["exact slow time on DLFT, Nh = 3"]
)
print(f"polynomial against the exact slow time at the same Nh = 3: {same_dynamics['cycles_to_0.5']:+.2%}")

# %%
# The histories, normalised by ``u0``; the exact one dashed.

fig, ax = plt.subplots(figsize=(6, 3.5))
for name, hist in runs.items():
    ax.semilogx(hist.cycles[1:], hist.wear[1:, 0] / hist.u0[0], label=name)
ax.semilogx(exact.cycles[1:], exact.wear[1:, 0] / exact.u0[0], "k--", label=exact.label)
ax.axhline(0.5, color="grey", lw=0.5)
ax.set(xlabel="cycles $N$", ylabel="$w / u_0$", title="10 N, 0.7 Hz, $K_w$ = 1e-11")
ax.legend(fontsize=8)
fig.tight_layout()
