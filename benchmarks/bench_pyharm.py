"""Code against code (issue 24): the ring-damper disk of pyHarm's tutorial 006 in pyHarm 1.2.2 and fretwear.

The model is :func:`fretwear.model.ring.ring_damper_disk` (24 sectors, ring sectors of 2e-3 kg, kr = 1e7,
Jenkins ring-disk contacts with kt = 1e8, mu = 0.1, N = mr R Omega^2 = 56.6 N, EO 1, 1 N on every tip,
modal damping 1e-3 on the disk). pyHarm gets the same matrices (a "blisk" and a "ring" substructure), one
``Jenkins`` connector per ring sector (its AFT element: ``k``, ``mu``, ``N0``) and one ``GOForcing`` per tip
with the phase ``2 pi EO i / N``, and runs the tutorial's analysis: arc-length continuation (``scipyroot``
solver, ``AllgowerPreconditioner``) over the tutorial's band, 0.95 to 1.1 times the 1-ND frequency
(169.344 Hz), with the odd harmonics up to ``--harmonics`` and ``--samples`` time samples. fretwear then
solves the same model at the frequencies pyHarm converged at (``fw.sweep``, same harmonics and samples), and
the script prints the FRF of blade 0's tip (norm of its harmonic coefficients, the tutorial's ``get_frf``)
from both codes, their largest relative difference and where, and the wall times of both in this run.

pyHarm runs in its own virtual environment, ``/work/venv-pyharm`` (created with ``pip install
pyharm-os==1.2.2`` if absent; never a fretwear dependency), in a subprocess.

    python benchmarks/bench_pyharm.py            # band/6 steps, ~12 points: ~2 min on 2 busy cores
    python benchmarks/bench_pyharm.py --full     # the tutorial's steps (band / 400): not timed, > 20 min

Measured (2 cores shared, load ~8; harmonics 1 and 3, 64 samples): default run 12 frequencies, pyHarm
107 s (analysis 101 s) against fretwear 2.0 s, ratio 53; ``--steps 10``: 18 frequencies, 214 s against
2.1 s, ratio 103 (``--steps 40``, pyHarm alone: 164 frequencies in 588 s). The tip amplitudes agree to
1e-14 wherever the contacts stick and to 1e-8 (largest 2.2e-8 on a coefficient) where they slip. Both codes
use the same law on the same grid: an AFT return map of the Jenkins element on the 64 samples
``t_j = j T / 64`` (fretwear's JENKINS kind has no DLFT penalty: its slot holds ``k_t``), so the stuck
points differ by round-off; in slip fretwear's answer does not move (to 1e-16) with ``tol = 1e-13`` or with
a full-period march instead of the half-wave one, so the 1e-8 is where pyHarm's nonlinear solve (scipy
``hybr`` under its arc-length corrector) stops. The comparison is at pyHarm's own converged frequencies, so
the continuation (arc length there, a frequency sweep here) does not enter the difference.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import fretwear as fw  # noqa: E402
from fretwear.model import DiskSector  # noqa: E402
from fretwear.model.ring import ring_damper_disk  # noqa: E402

VENV = Path("/work/venv-pyharm")
PYHARM = "pyharm-os==1.2.2"

#: the pyHarm side, run with the pyHarm venv's interpreter: input file in, results file out
WORKER = r"""
import json, sys, time
import numpy as np
t0 = time.perf_counter()
import pyHarm
t_import = time.perf_counter() - t0
d = np.load(sys.argv[1])
cfg = json.loads(str(d["cfg"]))
n = cfg["sectors"]
def sub(M, C, K):
    return {"matrix": {"M": M, "C": C, "K": K, "G": 0 * K}, "ndofs": 1}
frf = {"study": "frf", "puls_inf": cfg["puls_inf"], "puls_sup": cfg["puls_sup"], "ds_min": cfg["ds_min"],
       "ds_max": cfg["ds"], "ds0": cfg["ds"], "solver": "scipyroot",
       "reductors": [{"type": "AllgowerPreconditioner"}],
       "solver_options": {"root": {"method": "hybr", "options": {"xtol": cfg["xtol"]}}}, "verbose": False}
inp = {"system": {"type": "Base", "nh": cfg["harmonics"], "nti": cfg["samples"]},
       "substructures": {"blisk": sub(d["Md"], d["Cd"], d["Kd"]), "ring": sub(d["Mr"], 0 * d["Mr"], d["Kr"])},
       "connectors": {}, "analysis": {"FRF": frf}}
for i in range(n):
    inp["connectors"][f"F_{i:03d}"] = {"type": "GOForcing", "connect": {"blisk": [3 * i + 2]}, "dirs": [0],
                                       "amp": cfg["fex"], "dto": 0, "ho": 1,
                                       "phi": 2 * np.pi * cfg["engine_order"] * i / n}
    inp["connectors"][f"Jenkins_{i:03d}"] = {"type": "Jenkins", "connect": {"ring": [i], "blisk": [3 * i]},
                                             "dirs": [0], "mu": cfg["mu"], "N0": cfg["N0"], "k": cfg["kt"]}
t1 = time.perf_counter()
S = pyHarm.Maestro(inp)
S.operate()
t_run = time.perf_counter() - t1
idx = S.getIndex("blisk", 2, 0)
sols = [s for s in S.nls["FRF"].SolList if s.flag_accepted]
np.savez(sys.argv[2], omega=np.array([s.x[-1] for s in sols]), tip=np.array([s.x[idx] for s in sols]),
         t_import=t_import, t_run=t_run)
"""


def pyharm_python() -> Path:
    """The pyHarm venv's interpreter, the venv created and pyHarm installed first if absent."""
    python = VENV / "bin" / "python"
    if not python.exists():
        print(f"creating {VENV} with {PYHARM} (once) ...", flush=True)
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
        subprocess.run([str(python), "-m", "pip", "install", "--quiet", PYHARM], check=True,
                       stdin=subprocess.DEVNULL)  # fmt: skip
    return python


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--harmonics", type=int, default=3, help="highest (odd) harmonic, default 3")
    parser.add_argument("--samples", type=int, default=64, help="time samples per period, default 64")
    parser.add_argument("--steps", type=float, default=6, help="band / continuation step, default 6")
    parser.add_argument("--full", action="store_true", help="the tutorial's step, band / 400")
    args = parser.parse_args()
    steps = 400 if args.full else args.steps

    model = ring_damper_disk()
    n = model.info["sectors"]
    w1 = 2 * np.pi * DiskSector().frequencies(1)[0]  # the tutorial's band: 0.95 to 1.1 of the 1-ND mode
    lo, hi = 0.95 * w1, 1.1 * w1
    orders = list(range(1, args.harmonics + 1, 2))
    cfg = dict(sectors=n, harmonics=orders, samples=args.samples, puls_inf=lo, puls_sup=hi,
               ds=(hi - lo) / steps, ds_min=1e-6, xtol=1e-12, fex=model.info["fex"],
               engine_order=model.info["engine_order"], mu=model.info["mu"], N0=model.info["normal_load"],
               kt=model.info["kt"])  # fmt: skip
    d = 3 * n
    print(
        f"ring-damper disk: {n} sectors, {model.n_dofs} DOFs, {len(model.friction)} Jenkins contacts "
        f"(kt {cfg['kt']:.3g} N/m, mu {cfg['mu']}, N {cfg['N0']:.4g} N), EO {cfg['engine_order']}, "
        f"band {lo:.2f}-{hi:.2f} rad/s, harmonics {orders}, {args.samples} samples, step band/{steps:g}"
    )

    python = pyharm_python()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        np.savez(tmp / "in.npz", Md=model.M[:d, :d], Cd=model.C[:d, :d], Kd=model.K[:d, :d],
                 Mr=model.M[d:, d:], Kr=model.K[d:, d:], cfg=json.dumps(cfg))  # fmt: skip
        (tmp / "worker.py").write_text(WORKER)
        start = time.perf_counter()
        # in tmp: pyHarm writes a .pyHarm/ folder into its working directory
        run = subprocess.run([str(python), str(tmp / "worker.py"), str(tmp / "in.npz"), str(tmp / "out.npz")],
                             capture_output=True, text=True, cwd=tmp)  # fmt: skip
        t_pyharm = time.perf_counter() - start
        if run.returncode:
            sys.exit(f"pyHarm failed:\n{run.stderr[-3000:]}")
        out = np.load(tmp / "out.npz")
        omegas, ref, t_run = out["omega"], out["tip"], float(out["t_run"])

    start = time.perf_counter()
    sweep = fw.sweep(model, omegas, args.harmonics, samples=args.samples)
    t_fw = time.perf_counter() - start
    cols = [c for k in orders for c in (2 * k - 1, 2 * k)]  # a_k, b_k in fretwear's full layout
    mine = np.array([s.dof_harmonics[2, cols] for s in sweep.solutions])
    amp_ref, amp = np.linalg.norm(ref, axis=1), np.linalg.norm(mine, axis=1)
    rel = np.abs(amp - amp_ref) / amp_ref
    coef = np.abs(mine - ref).max(axis=1) / np.abs(ref).max(axis=1)

    print(f"\n{'omega rad/s':>12} {'f Hz':>9} {'pyHarm |u_tip0| m':>18} {'fretwear':>18} {'rel diff':>9} "
          f"{'coef diff':>9}  contacts")  # fmt: skip
    for i, s in enumerate(sweep.solutions):
        slip = int(np.any(s.state == fw.model.SLIP, axis=1).sum())
        print(f"{omegas[i]:12.4f} {omegas[i] / (2 * np.pi):9.4f} {amp_ref[i]:18.10e} {amp[i]:18.10e} "
              f"{rel[i]:9.2e} {coef[i]:9.2e}  {slip:2d}/{n} slip")  # fmt: skip
    j = int(np.argmax(coef))
    print(f"\n{len(omegas)} frequencies, fretwear converged at all: {bool(np.all(sweep.converged))}")
    k = int(np.argmax(rel))
    print(f"max relative difference of the tip amplitude {rel[k]:.3g} (at {omegas[k]:.4f} rad/s); "
          f"of its harmonic coefficients {coef[j]:.3g} (at {omegas[j]:.4f} rad/s)")  # fmt: skip
    print(f"wall time: pyHarm {t_pyharm:.2f} s (subprocess; analysis {t_run:.2f} s), "
          f"fretwear sweep {t_fw:.3f} s; ratio pyHarm / fretwear {t_pyharm / t_fw:.3g} "
          f"(analysis alone {t_run / t_fw:.3g})")  # fmt: skip


if __name__ == "__main__":
    main()
