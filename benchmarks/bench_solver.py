"""Wall-time benchmarks of the periodic solver (not a test).

Run from the repository root::

    python benchmarks/bench_solver.py            # about two minutes on 2 cores (a cold compilation)
    python benchmarks/bench_solver.py --quick    # under a minute: fewer repeats, no cold start

Prints three tables, each figure next to its target and the ratio:

1. warm timings (median over repeats, after a warm-up call that compiles the
   kernels) of a 101-point frequency sweep (:func:`fretwear.sweep`, the
   compiled sweep) and of the same sweep point by point in Python
   (``fretwear.hbm.continuation.sweep(..., compiled=False)``, the solver before
   the compiled sweep, timed in turn with it so that the machine's load hits
   both alike), at ``Nh = 7`` and ``21``, for (a) the paper's 2-DOF model at
   ``F_ex = 10 N`` over 0.3-1.3 Hz and (b) the 1-DOF oscillator with a Jenkins
   element (:func:`fretwear.jenkins_oscillator`, omega 0.5-2.5 rad/s); and one
   single-frequency solve (:func:`fretwear.solve_periodic`);
2. start-up: ``fretwear frf --fmin 0.3 --fmax 1.3 --n 101 --harmonics 21`` in a
   new process, time to its first line of output, with an empty Numba cache
   (import + compile; skipped with ``--quick``) and with the cache it filled;
   and the compile time of each kernel group of :mod:`fretwear.compile`;
3. the transform of the AFT scheme at the sizes the solver uses: the matrix
   DFT of the library (``HarmonicBasis.analysis @ signal`` inside ``njit``)
   against a radix-2 real FFT written here in Numba, per transform.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numba import njit

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from timing import fmt_time, table  # noqa: E402

from fretwear import jenkins_oscillator, paper_model, solve_periodic, sweep  # noqa: E402
from fretwear.hbm.harmonics import HarmonicBasis, default_samples  # noqa: E402
from fretwear.hbm.periodic import Problem, solve_problem  # noqa: E402

#: warm 101-point sweep targets (s), by Nh, for both models
SWEEP_TARGETS = {7: 2e-3, 21: 10e-3}
#: start-up targets (s): the first command with an empty Numba cache, then from the cache
COLD_TARGET, CACHED_TARGET = 15.0, 1.0

CASES = {
    "paper, F_ex = 10 N": (paper_model(fex=10.0), 2 * np.pi * 0.7, 2 * np.pi * np.linspace(0.3, 1.3, 101)),
    "Jenkins 1-DOF": (jenkins_oscillator(), 1.5, np.linspace(0.5, 2.5, 101)),
}

COMMAND = ["-m", "fretwear", "frf", "--fmin", "0.3", "--fmax", "1.3", "--n", "101", "--harmonics", "21",
           "--out", "-"]  # fmt: skip

CHILD_COMPILE = """
import json, os, sys, time
import fretwear.compile as fc
print(json.dumps(fc.warm(*sys.argv[1:])))
"""


def median_time(fn: Callable[[], object], repeats: int) -> float:
    """Median wall time (s) of ``fn()`` over ``repeats`` calls, after one warm-up call."""
    return interleaved_medians([fn], repeats)[0]


def interleaved_medians(fns: list[Callable[[], object]], repeats: int) -> list[float]:
    """Median wall time (s) of each of ``fns``, timed in turn so that load changes hit all alike."""
    for fn in fns:
        fn()
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(repeats):
        for fn, t in zip(fns, times, strict=True):
            t0 = time.perf_counter()
            fn()
            t.append(time.perf_counter() - t0)
    return [statistics.median(t) for t in times]


# -- 1. warm solver timings -----------------------------------------------------------
def warm(quick: bool) -> None:
    """Table 1: warm 101-point sweeps, compiled and point by point, and single solves."""
    print("1. Warm timings: median wall time after a compiling warm-up call", flush=True)
    rows = []
    for name, (model, omega, omegas) in CASES.items():
        for nh in (7, 21):
            compiled, by_point = interleaved_medians(
                [lambda m=model, w=omegas, n=nh: sweep(m, w, n),
                 lambda m=model, w=omegas, n=nh: sweep(m, w, n, compiled=False)],
                3 if quick else 11,
            )  # fmt: skip
            single = median_time(lambda m=model, w=omega, n=nh: solve_periodic(m, w, n), 5 if quick else 21)
            n_ok = int(sweep(model, omegas, nh).converged.sum())
            target = SWEEP_TARGETS[nh]
            rows.append([
                name, nh, fmt_time(compiled), fmt_time(target), f"{compiled / target:.2f}",
                fmt_time(by_point), f"{by_point / compiled:.1f}x", f"{n_ok}/{len(omegas)}", fmt_time(single),
            ])  # fmt: skip
    header = ["model", "Nh", "101-pt sweep", "target", "measured/target", "point by point", "speed-up",
              "converged", "one solve"]  # fmt: skip
    table(header, rows)
    print(
        "101-pt sweep: fretwear.sweep (compiled, one call); point by point: the same sweep through\n"
        "solve_problem frequency by frequency (the solver before the compiled sweep), timed in turn.\n",
        flush=True,
    )


# -- 2. start-up -------------------------------------------------------------------------
def first_line(env: dict) -> tuple[float, float]:
    """Wall time (s) of a new ``fretwear frf`` process to its first line of output, and to its end."""
    t0 = time.perf_counter()
    with subprocess.Popen([sys.executable, *COMMAND], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True) as proc:  # fmt: skip
        proc.stdout.readline()
        first = time.perf_counter() - t0
        _, err = proc.communicate()
    if proc.returncode != 0:
        raise RuntimeError(f"fretwear frf failed ({proc.returncode}): {err}")
    return first, time.perf_counter() - t0


def start_up(quick: bool) -> None:
    """Table 2: a new process running ``fretwear frf`` with an empty, then a filled, Numba cache."""
    print(
        f"2. Start-up: new process, 'fretwear {' '.join(COMMAND[2:])}', to its first output line", flush=True
    )
    rows = []
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
    }
    with tempfile.TemporaryDirectory(prefix="fretwear-numba-cache-") as cache:
        if quick:  # the package's own cache, filled by table 1 (this process compiled the sweep)
            starts = [("from the Numba cache", env, CACHED_TARGET)]
        else:
            cold = {**env, "NUMBA_CACHE_DIR": cache}
            starts = [
                ("cold (empty Numba cache)", cold, COLD_TARGET),
                ("from the Numba cache", cold, CACHED_TARGET),
            ]
        for label, child_env, target in starts:
            first, end = first_line(child_env)
            rows.append([label, fmt_time(first), fmt_time(end), fmt_time(target), f"{first / target:.2f}"])
    table(["start", "to first line", "to exit", "target", "measured/target"], rows)
    if quick:
        return
    import fretwear.compile as fc

    rows = []
    for name, kernel in fc.KERNELS.items():
        with tempfile.TemporaryDirectory(prefix="fretwear-numba-cache-") as cache:
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-c", CHILD_COMPILE, name], env={**env, "NUMBA_CACHE_DIR": cache},
                           check=True, capture_output=True, text=True)  # fmt: skip
            wall = time.perf_counter() - t0
        rows.append([name, fmt_time(wall), fmt_time(kernel.seconds), f"{wall / kernel.seconds:.2f}"])
    table(["kernel group", "new process, empty cache", "announced", "measured/announced"], rows)


# -- 3. matrix DFT against a radix-2 real FFT -----------------------------------------------
@njit(cache=True, nogil=True)
def _fft_from_bitreversed(a, twiddle):
    """In-place radix-2 decimation-in-time FFT of ``a`` (length ``L = 2^p``) given in bit-reversed order.

    ``twiddle[k] = exp(-2 pi i k / L)`` for ``k < L / 2``.
    """
    n = a.shape[0]
    size = 2
    while size <= n:
        half = size // 2
        stride = n // size
        for start in range(0, n, size):
            for k in range(half):
                i = start + k
                t = twiddle[k * stride] * a[i + half]
                a[i + half] = a[i] - t
                a[i] = a[i] + t
        size *= 2


@njit(cache=True, nogil=True)
def fft_half_wave(x, rev, pre, post, twiddle, work, out):
    """Odd-harmonic coefficients ``[a1, b1, a3, b3, ...]`` of ``M`` real half-period samples ``x``.

    With ``Y_m = sum_n x_n exp(-i pi n (2m + 1) / M)``, ``a_(2m+1) = 2 Re Y_m / M`` and
    ``b_(2m+1) = -2 Im Y_m / M``. Even and odd samples are packed into one complex
    sequence of length ``L = M / 2``, pre-twisted by ``pre[p] = exp(-i pi p / L)``
    and transformed by one FFT of length ``L``; the Hermitian symmetry of the
    odd-frequency DFT of a real sequence separates the two halves again, and
    ``post[m] = exp(-i pi (2m + 1) / M)`` joins them.
    """
    L = work.shape[0]
    for p in range(L):
        work[rev[p]] = complex(x[2 * p], x[2 * p + 1]) * pre[p]
    _fft_from_bitreversed(work, twiddle)
    scale = 2.0 / x.shape[0]
    for m in range(out.shape[0] // 2):
        c = work[m]
        d = work[L - 1 - m].conjugate()
        y = 0.5 * (c + d) - 0.5j * (c - d) * post[m]
        out[2 * m] = scale * y.real
        out[2 * m + 1] = -scale * y.imag


@njit(cache=True, nogil=True)
def fft_full_wave(x, rev, post, twiddle, work, out):
    """Coefficients ``[a0, a1, b1, ..., aNh, bNh]`` of ``N`` real samples ``x`` over a period.

    The classic real FFT: one complex FFT of length ``N / 2`` of ``x_2p + i x_2p+1``,
    split into the transforms of the even and odd samples and joined with
    ``post[k] = exp(-2 pi i k / N)``.
    """
    L = work.shape[0]
    for p in range(L):
        work[rev[p]] = complex(x[2 * p], x[2 * p + 1])
    _fft_from_bitreversed(work, twiddle)
    n = x.shape[0]
    for k in range((out.shape[0] + 1) // 2):
        c = work[k]
        d = work[(L - k) % L].conjugate()
        y = 0.5 * (c + d) - 0.5j * (c - d) * post[k]
        if k == 0:
            out[0] = y.real / n
        else:
            out[2 * k - 1] = 2.0 * y.real / n
            out[2 * k] = -2.0 * y.imag / n


class RealFFT:
    """Tables of :func:`fft_half_wave` / :func:`fft_full_wave` for one :class:`HarmonicBasis`.

    Parameters
    ----------
    basis : HarmonicBasis
        Basis whose :attr:`~HarmonicBasis.analysis` the transform reproduces;
        its marched sample count must be a power of two (>= 4).
    """

    def __init__(self, basis: HarmonicBasis) -> None:
        self.basis = basis
        M = basis.marched_samples
        L = M // 2
        bits = L.bit_length() - 1
        self.rev = np.array([int(f"{p:0{bits}b}"[::-1], 2) if bits else 0 for p in range(L)], dtype=np.int64)
        self.twiddle = np.exp(-2j * np.pi * np.arange(max(L // 2, 1)) / L)
        self.work = np.empty(L, dtype=np.complex128)
        if basis.half_wave:
            self.pre = np.exp(-1j * np.pi * np.arange(L) / L)
            self.post = np.exp(-1j * np.pi * (2 * np.arange(L) + 1) / M)
        else:
            self.post = np.exp(-2j * np.pi * np.arange(L) / M)

    def __call__(self, x: np.ndarray, out: np.ndarray) -> None:
        if self.basis.half_wave:
            fft_half_wave(x, self.rev, self.pre, self.post, self.twiddle, self.work, out)
        else:
            fft_full_wave(x, self.rev, self.post, self.twiddle, self.work, out)


@njit(cache=True, nogil=True)
def _loop_matrix(analysis, signals, out, passes):
    for _ in range(passes):
        for r in range(signals.shape[0]):
            out[r] = analysis @ signals[r]


@njit(cache=True, nogil=True)
def _loop_half_wave(signals, rev, pre, post, twiddle, work, out, passes):
    for _ in range(passes):
        for r in range(signals.shape[0]):
            fft_half_wave(signals[r], rev, pre, post, twiddle, work, out[r])


@njit(cache=True, nogil=True)
def _loop_full_wave(signals, rev, post, twiddle, work, out, passes):
    for _ in range(passes):
        for r in range(signals.shape[0]):
            fft_full_wave(signals[r], rev, post, twiddle, work, out[r])


def transform_row(half_wave: bool, nh: int, repeats: int) -> list:
    """Table row comparing the matrix DFT and the FFT kernel for one basis, with DLFT context."""
    basis = HarmonicBasis(nh, default_samples(nh), half_wave)
    n_signals = 256
    signals = np.random.default_rng(nh).standard_normal((n_signals, basis.marched_samples))
    ref, got = np.empty((n_signals, basis.size)), np.empty((n_signals, basis.size))
    passes = max(1, 200_000 // (basis.size * basis.marched_samples))
    fft = RealFFT(basis)
    if half_wave:
        tables, loop = (fft.rev, fft.pre, fft.post, fft.twiddle, fft.work), _loop_half_wave
    else:
        tables, loop = (fft.rev, fft.post, fft.twiddle, fft.work), _loop_full_wave
    t_matrix, t_fft = (
        t / (passes * n_signals)
        for t in interleaved_medians(
            [
                lambda: _loop_matrix(basis.analysis, signals, ref, passes),
                lambda: loop(signals, *tables, got, passes),
            ],
            repeats,
        )
    )
    error = np.abs(got - ref).max() / np.abs(ref).max()
    if error > 1e-12:
        raise AssertionError(f"FFT coefficients differ from the matrix DFT by {error:.2g} (Nh = {nh})")
    # context: one DLFT evaluation (one iDFT + one DFT per contact) of the paper model at 0.7 Hz
    problem = Problem(paper_model(), 2 * np.pi * 0.7, nh, half_wave=half_wave)
    x = solve_problem(problem).unknowns
    t_res, t_jac = interleaved_medians(
        [lambda: problem.evaluate(x, jacobian=False), lambda: problem.evaluate(x)], 20 * repeats
    )
    return [
        "half" if half_wave else "full", nh, basis.samples, basis.marched_samples, basis.size,
        fmt_time(t_matrix), fmt_time(t_fft), "matrix DFT" if t_matrix < t_fft else "FFT",
        f"{max(t_matrix, t_fft) / min(t_matrix, t_fft):.2g}x", f"{error:.0e}",
        fmt_time(t_res), fmt_time(t_jac), f"{2 * t_matrix / t_res:.0%}", f"{2 * t_matrix / t_jac:.0%}",
    ]  # fmt: skip


def transforms(quick: bool) -> None:
    """Table 3: matrix DFT against the radix-2 real FFT, half- and full-wave, Nh = 7, 21, 41."""
    print("3. One DFT of the AFT scheme (samples -> harmonics), per transform, in Numba", flush=True)
    repeats = 5 if quick else 25
    rows = [transform_row(half_wave, nh, repeats) for half_wave in (True, False) for nh in (7, 21, 41)]
    header = [
        "wave", "Nh", "N", "marched", "H", "matrix DFT", "radix-2 rFFT", "faster", "by", "rel. diff",
        "residual", "residual+Jacobian", "2 DFTs/residual", "2 DFTs/res.+Jac.",
    ]  # fmt: skip
    table(header, rows)
    print(
        "residual, residual+Jacobian: one Problem.evaluate of the paper model at 0.7 Hz: one iDFT and\n"
        "one DFT per contact, the march and, with the Jacobian, the O(samples H^2) derivative blocks.\n"
    )


def main(argv: list[str] | None = None) -> None:
    """Run the benchmarks (``--quick``: fewer repeats, no cold start)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, no cold start: under a minute")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"fretwear benchmarks on {os.cpu_count()} cores (load average {load:.1f}), "
          f"Python {sys.version.split()[0]}\n")  # fmt: skip
    warm(args.quick)
    start_up(args.quick)
    transforms(args.quick)
    print(f"total {fmt_time(time.perf_counter() - t0)}")


if __name__ == "__main__":
    main()
