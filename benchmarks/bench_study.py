"""Study benchmarks (issue 13): speed-up of 2 Dask workers over 1, overhead per task, cost vs points.

Run ``python benchmarks/bench_study.py`` (``--quick`` for smaller studies, ``--samples N`` for the
speed-up study). The study is the shipped wear-life example (``fretwear/data/wear_life.toml``:
paper model at 0.7 Hz, ``mu`` and ``F_ex`` random, ``Nh = 21``, exact load path) with fewer samples.
Each cluster is started and warmed up (one wear history per worker, which loads the compiled kernels)
before the clock starts; the start-up is printed apart. Figures:

* speed-up: wall time of the study on 1 worker over that on 2 (target >= 1.7 on 2 cores);
* overhead per task: ``(workers * wall - summed task compute) / tasks`` and as a share of the workers'
  time (target < 5 %); it includes the idle tail at the end of a study;
* cost against the number of points (2 workers).

The load average of the machine is printed before and after each figure: on a shared machine the
speed-up can only be as good as the free cores.
"""

from __future__ import annotations

import argparse
import logging
import os
import tempfile
import time
from pathlib import Path

import numpy as np

import fretwear as fw
from fretwear.studies.layout import layout
from fretwear.studies.run import run_study
from fretwear.studies.spec import read_spec

EXAMPLE = Path(fw.__file__).parent / "data" / "wear_life.toml"


def load() -> str:
    return "load average " + " ".join(f"{x:.2f}" for x in os.getloadavg())


def warm_up() -> int:
    """One wear history at the example's settings: loads the compiled kernels in a worker."""
    fw.wear_history(fw.paper_model(), 2 * np.pi * 0.7, "exact", kw=1e-11, cycles=1e7, harmonics=21)
    return os.getpid()


def cluster(workers: int):
    from distributed import Client, LocalCluster

    start = time.perf_counter()
    lc = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)  # fmt: skip
    client = Client(lc, set_as_default=False)
    up = time.perf_counter() - start
    client.run(warm_up)
    return lc, client, up, time.perf_counter() - start - up


def study(client, samples: int, folder: Path, tag: str):
    spec = read_spec(EXAMPLE, samples=samples)
    before = load()
    run = run_study(spec, folder / f"{tag}.zarr", client=client, progress=False)
    return spec, run, before, load()


def line(spec, run) -> str:
    per_task = int(np.prod(layout(spec).chunks))
    return (
        f"{spec.n_points} points in {run.n_tasks} tasks of up to {per_task}: wall {run.wall_time:.2f} s, "
        f"summed task compute {run.compute_seconds:.2f} s "
        f"({run.compute_seconds / spec.n_points * 1e3:.1f} ms per point, "
        f"CPU share {run.cpu_seconds / run.compute_seconds:.2f}); overhead per task "
        f"{run.overhead_per_task * 1e3:.1f} ms = {100 * run.overhead_fraction:.1f} % of the workers' time "
        f"(target < 5 %: x{run.overhead_fraction / 0.05:.2f})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller studies")
    parser.add_argument("--samples", type=int, default=None, help="points of the speed-up study (>= 200)")
    parser.add_argument("--repeat", type=int, default=2, help="alternate 1 and 2 workers this many times")
    args = parser.parse_args()
    samples = args.samples or (200 if args.quick else 400)
    sizes = (50, 100, 200) if args.quick else (50, 100, 200, 400, 800)
    print(f"cores {len(os.sched_getaffinity(0))}; {load()}")
    walls: dict[int, list[float]] = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for rep in range(args.repeat):
            for workers in (1, 2):
                lc, client, up, warm = cluster(workers)
                spec, run, before, after = study(client, samples, folder, f"speedup{workers}-{rep}")
                walls[workers].append(run.wall_time)
                print(f"{workers} worker(s) (cluster start {up:.2f} s, warm-up {warm:.2f} s): "
                      f"{line(spec, run)}; {before} -> {after}")  # fmt: skip
                if workers == 2 and rep == args.repeat - 1:
                    print("cost against the number of points (2 workers):")
                    print(f"  {'points':>7} {'tasks':>6} {'wall s':>8} {'ms/point':>9} {'overhead %':>10} "
                          f"{'CPU share':>9}  load (1 min)")  # fmt: skip
                    for n in sizes:
                        spec, r, before, after = study(client, n, folder, f"size{n}")
                        loads = f"{before.split()[-3]} -> {after.split()[-3]}"
                        print(f"  {n:>7} {r.n_tasks:>6} {r.wall_time:>8.2f} {r.wall_time / n * 1e3:>9.2f} "
                              f"{100 * r.overhead_fraction:>10.1f} "
                              f"{r.cpu_seconds / r.compute_seconds:>9.2f}  {loads}")  # fmt: skip
                client.close()
                lc.close()
    speedup = min(walls[1]) / min(walls[2])
    print(f"speed-up of 2 workers over 1 ({samples} points, best of {args.repeat}): {speedup:.2f}x "
          f"(target >= 1.7x: ratio {speedup / 1.7:.2f}); {load()}")  # fmt: skip


if __name__ == "__main__":
    main()
