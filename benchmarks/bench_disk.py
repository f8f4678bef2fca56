"""The tuned shrouded disk: the cyclic sector solve against the full-disk solve, same equations.

For the default 24-sector disk (shroud of Jenkins contacts, ``F_ex`` 2 N,
engine order 1 and 3) a sweep of ``--points`` frequencies through the blade
resonance, solved on the full disk (``fw.sweep``: 24 contacts, receptance
form) and on one sector (:func:`fretwear.disk.sweep_sector`: one contact), on
the same time grid. Printed per case: the largest relative difference of the
DOF harmonics (target 1e-8), the share of slipping samples, both wall times
(best of ``--repeat``) and the speed-up (target >= 10).

    python benchmarks/bench_disk.py
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense solves: threads only contend

import numpy as np  # noqa: E402
from timing import best_of, fmt_time, table  # noqa: E402

import fretwear as fw  # noqa: E402
from fretwear.disk import samples_for, sweep_sector  # noqa: E402
from fretwear.model import SLIP  # noqa: E402

#: (engine order, band in Hz) through the blade family's resonance with the shroud in partial slip
CASES = ((1, (164.0, 176.0)), (3, (196.0, 214.0)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=41, help="frequencies per sweep (default 41)")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs, best kept (default 3)")
    args = parser.parse_args()
    rows = []
    for eo, band in CASES:
        model = fw.bladed_disk(engine_order=eo, fex=2.0)
        omegas = 2 * np.pi * np.linspace(*band, args.points)
        for nh in (7, 21):
            samples = samples_for(24, eo, nh)
            sweep_sector(model, omegas[:2], nh)  # compile and warm both paths
            fw.sweep(model, omegas[:2], nh, samples=samples)
            t_full, full = best_of(lambda: fw.sweep(model, omegas, nh, samples=samples), args.repeat)  # noqa: B023
            t_cyc, cyc = best_of(lambda: sweep_sector(model, omegas, nh), args.repeat)  # noqa: B023
            diff = max(
                np.abs(c.dof_harmonics - f.dof_harmonics).max() / np.abs(f.dof_harmonics).max()
                for c, f in zip(cyc.solutions, full.solutions, strict=True)
            )
            slip = np.mean([np.mean(s.state == SLIP) for s in full.solutions])
            ok = all(full.converged) and all(cyc.converged)
            speed = f"{t_full / t_cyc:.0f}x"
            rows.append([eo, f"{band[0]:g}-{band[1]:g}", nh, samples, f"{slip:.2f}", f"{diff:.1e}", "1e-8",
                         fmt_time(t_full), fmt_time(t_cyc), speed, ">= 10x", ok])  # fmt: skip
    table(["EO", "band Hz", "Nh", "samples", "slip", "difference", "target", "full disk", "sector",
           "speed-up", "target", "converged"], rows)  # fmt: skip


if __name__ == "__main__":
    main()
