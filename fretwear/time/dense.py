"""Small dense linear algebra of the time kernels, written out so that every product sums in a fixed order.

The matrices are small (the state of a pattern, the stuck contacts of an
event): plain loops, no allocation, and the same round-off in every kernel
that uses them.
"""

from __future__ import annotations

from numba import njit

__all__ = ["back_substitute", "matmul_into", "matvec_into"]


@njit(cache=True, nogil=True, inline="always")
def matmul_into(A, B, out):
    """``out = A @ B`` (no allocation; ``out`` distinct from both), each entry summed over ``q`` in turn."""
    for i in range(A.shape[0]):
        for j in range(B.shape[1]):
            t = 0.0
            for q in range(A.shape[1]):
                t += A[i, q] * B[q, j]
            out[i, j] = t


@njit(cache=True, nogil=True, inline="always")
def matvec_into(A, x, out):
    """``out = (A @ x)[: len(out)]``: the first ``len(out)`` rows of ``A`` times ``x`` (no allocation)."""
    for i in range(out.shape[0]):
        t = 0.0
        for q in range(x.shape[0]):
            t += A[i, q] * x[q]
        out[i] = t


@njit(cache=True, nogil=True)
def back_substitute(U, x):
    """``x <- U^-1 x`` in place, ``U`` upper triangular with a non-zero diagonal."""
    m = U.shape[0]
    for r in range(m - 1, -1, -1):
        for q in range(r + 1, m):
            x[r] -= U[r, q] * x[q]
        x[r] /= U[r, r]
