"""Linear mistuning of the 24-sector bladed disk: the magnification curve and Whitehead's bound.

For each mistuning level (standard deviation of the blade stiffness
deviations ``delta_i``), ``--draws`` seeded patterns; per pattern the amplitude
magnification factor (largest blade-tip amplitude over the tuned peak, in the
same band: :func:`fretwear.disk.magnification`). Printed: the curve (mean, 95th
percentile and largest factor against the level; it grows, peaks, then falls)
in the blade-dominated family, checked against Whitehead's bound
``(1 + sqrt(24)) / 2 = 2.95``; then the largest factor in each of the three
resonances of the engine order (+-10 %), and where, with the wall time per draw.

    python benchmarks/bench_mistuning.py            # 1000 draws per level
    python benchmarks/bench_mistuning.py --quick    # 100
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # 72 x 72 eigenproblems: threads only contend

import numpy as np  # noqa: E402
from timing import table  # noqa: E402

from fretwear.disk import draw_mistuning, magnification  # noqa: E402
from fretwear.model import DiskSector  # noqa: E402

LEVELS = (0.0, 0.0025, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.03, 0.05, 0.075, 0.1)
#: the blade-dominated family of the issue (one mode per blade: Whitehead's assumption)
BLADE_FAMILY = (165.0, 200.0)
ENGINE_ORDER = 3


def family_bands(sector: DiskSector, engine_order: int, width: float = 0.1) -> list[tuple[float, float]]:
    """About each of the sector's three modes at ``nd = engine_order`` (the tuned resonances), +-``width``
    (Hz); where mode families come close (veering) a band holds modes of two families."""
    return [(f * (1 - width), f * (1 + width)) for f in sector.frequencies(engine_order)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=1000, help="patterns per level (default 1000)")
    parser.add_argument("--quick", action="store_true", help="100 draws per level")
    args = parser.parse_args()
    draws = 100 if args.quick else args.draws
    bands = family_bands(DiskSector(), ENGINE_ORDER)
    print(f"engine order {ENGINE_ORDER}, {draws} draws per level", flush=True)
    rows, worst, start = [], [], time.perf_counter()
    for level in LEVELS:
        res = magnification(
            draw_mistuning(24, level, draws, seed=2007), BLADE_FAMILY, engine_order=ENGINE_ORDER
        )
        f = res.factor
        rows.append([f"{100 * level:g}", f"{f.mean():.3f}", f"{np.percentile(f, 95):.3f}", f"{f.max():.3f}",
                     "yes" if f.max() <= res.whitehead else "NO"])  # fmt: skip
        worst.append(f.max())
    per_draw = (time.perf_counter() - start) / (draws * len(LEVELS))
    print(f"blade family {BLADE_FAMILY[0]:g}-{BLADE_FAMILY[1]:g} Hz (Whitehead bound {res.whitehead:.3f}):")
    table(["level %", "mean", "95th pct", "largest", "<= bound"], rows)
    peak_level = LEVELS[int(np.argmax(worst))]
    print(
        f"largest factor {max(worst):.3f} at level {100 * peak_level:g} %; {1e3 * per_draw:.1f} ms per draw\n"
    )
    rows = []
    for j, band in enumerate(bands):
        best = (0.0, 0.0, 0.0, 0)
        for level in LEVELS[1:]:
            res = magnification(draw_mistuning(24, level, max(draws // 10, 20), seed=7), band,
                                engine_order=ENGINE_ORDER)  # fmt: skip
            k = int(np.argmax(res.factor))
            if res.factor[k] > best[0]:
                best = (res.factor[k], level, res.frequency[k], res.blade[k])
        if min(abs(res.tuned_frequency - e) for e in band) < 1e-6 * band[1]:  # the tip force misses the mode
            rows.append([j + 1, f"{band[0]:.1f}-{band[1]:.1f}", "none: tuned peak at the band's edge"])
            continue
        rows.append([j + 1, f"{band[0]:.1f}-{band[1]:.1f}", f"{res.tuned_frequency:.2f}", f"{best[0]:.3f}",
                     f"{100 * best[1]:g}", f"{best[2]:.2f}", best[3],
                     "yes" if best[0] <= res.whitehead else "NO"])  # fmt: skip
    print("largest factor about each tuned resonance, +-10 % (fewer draws per level):")
    header = ["family", "band Hz", "tuned peak Hz", "largest", "level %", "at Hz", "blade", "<= bound"]
    table(header, [r + [""] * (len(header) - len(r)) for r in rows])


if __name__ == "__main__":
    main()
