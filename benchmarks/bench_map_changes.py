"""Wear-map changes in process: what the dashboard computes and draws for a new k_w, Nh, method or band.

The same sequence of changes as ``bench_app.py``'s wear-map timings (``map_changes``), without a server
or a browser: a :class:`~app.session.Session` on the wear-map scene runs inline (no executor) on the
server's backend (two worker threads) and a fresh result cache, after the server's warm-up (kernels
loaded, the default exact map's sliding tables built). Each change is timed from the control's new
value to the results published (``compute``) and to the scene's three figures built (the HoloViews
objects the page renders); apart, the figures rendered to Bokeh models (``hv.render``, about what the
server does before it sends them); the browser adds the transfer and the drawing.

    python benchmarks/bench_map_changes.py            # 5 values of each change
    python benchmarks/bench_map_changes.py --quick    # 3

Each figure is printed next to ``WEAR_MAP_CHANGE`` (``bench_app.py``) with the ratio, and the load
average: on a loaded machine every figure grows.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the server's warm-up sets it


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="3 values of each change")
    moves = 3 if parser.parse_args().quick else 5

    import holoviews as hv
    from bench_app import WEAR_MAP_CHANGE

    from app.backend import Backend, ResultCache
    from app.session import Session
    from app.state import Controls
    from app.warmup import compile_kernels, warm_tables

    hv.extension("bokeh")
    start = time.perf_counter()
    compile_kernels()
    warm_tables()
    warm = time.perf_counter() - start
    controls = Controls()
    session = Session(controls, backend=Backend(), cache=ResultCache(), start=False)
    session.scene = "wearmap"
    session.start()
    scene = session.current

    def timed(name: str, value) -> tuple[float, float, float, float]:
        """Seconds to the results published and to the figures built, CPU seconds of the process (every
        thread) for both, and seconds of the figures' Bokeh rendering."""
        t0, cpu = time.perf_counter(), time.process_time()
        setattr(controls, name, value)
        t1 = time.perf_counter()
        built = [scene.figure(figure, live=True) for figure in scene.figure_names]
        t2, cpu = time.perf_counter(), time.process_time() - cpu
        for figure in built:
            hv.render(figure, backend="bokeh")
        return t1 - t0, t2 - t0, cpu, time.perf_counter() - t2

    timed("kw", controls.kw)  # the first figures (plotting code loaded)
    out: dict[str, list[tuple[float, float, float, float]]] = {
        "k_w": [],
        "Nh": [],
        "k_w_dlft": [],
        "method": [],
        "band": [],
    }
    for k in range(moves):
        out["k_w"].append(timed("kw", float(f"{1.1 + 0.1 * k:.2g}e-11")))
    timed("dynamics", "dlft")
    for nh in (9, 5, 11, 3, 13)[:moves]:
        out["Nh"].append(timed("harmonics", nh))
    timed("harmonics", 7)
    for k in range(moves):  # k_w on the DLFT dynamics: the exact load path's histories rescale
        out["k_w_dlft"].append(timed("kw", float(f"{2.1 + 0.1 * k:.2g}e-11")))
    timed("dynamics", "shooting")
    for method in ("polynomial", "stepping"):
        out["method"].append(timed("method", method))
    timed("method", "exact")
    for k in range(moves):
        out["band"].append(timed("fmin", 0.31 + 0.02 * k))
    load = os.getloadavg()
    print(f"fretwear wear-map changes in process, {os.cpu_count()} CPUs, load average {load[0]:.1f} "
          f"{load[1]:.1f} {load[2]:.1f} (1, 5, 15 min); warm-up {warm:.1f} s")  # fmt: skip
    for kind, what in (
        ("k_w", "k_w"),
        ("Nh", "Nh (DLFT)"),
        ("k_w_dlft", "k_w (DLFT)"),
        ("method", "method"),
        ("band", "band's f_min"),
    ):
        compute, whole, cpu, render = (list(column) for column in zip(*out[kind], strict=True))
        median = statistics.median(whole)
        print(f"wear map: {what:<13} median {median:.3f} s (min {min(whole):.3f}, max {max(whole):.3f}, "
              f"n = {len(whole)}; compute {statistics.median(compute):.3f} s, "
              f"CPU {statistics.median(cpu):.3f} s)"
              f"  target <= {WEAR_MAP_CHANGE:g} s  ratio {median / WEAR_MAP_CHANGE:.2f};"
              f"  then Bokeh render {statistics.median(render):.3f} s")  # fmt: skip
    (_, poly, poly_cpu, _), (_, stepping, stepping_cpu, _) = out["method"]
    print(f"  method: polynomial {poly:.3f} s (CPU {poly_cpu:.3f} s), stepping {stepping:.3f} s "
          f"(CPU {stepping_cpu:.3f} s), each its first map at these settings")  # fmt: skip


if __name__ == "__main__":
    main()
