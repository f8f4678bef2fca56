"""Small dense linear algebra for the compiled kernels: LU factorisation with partial pivoting.

Numba's ``np.linalg`` raises on a singular matrix, which would abort a whole
compiled sweep, and costs a LAPACK call with copies and checks per solve,
which dominates at the sizes of harmonic balance (tens of unknowns). These
loops report a zero pivot instead and give the sign of the determinant,
which orients the piecewise-linear walks.
"""

from __future__ import annotations

from numba import njit

__all__ = ["lu_factor", "lu_solve", "FASTMATH"]

#: Numba's floating-point licences for the harmonic-balance kernels: reassociation (sums vectorised),
#: fused multiply-adds, reciprocals for divisions, no signed zeros; worth 15 % on a sweep at the same
#: answers to 3e-14. Not "nnan" or "ninf": the kernels test for non-finite values and report them.
FASTMATH = {"reassoc", "contract", "arcp", "nsz"}


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def lu_factor(a, piv):
    """LU factorisation of the square ``a`` with partial pivoting, in place.

    Returns the sign of ``det a``, or 0 if a pivot is exactly zero (singular, as
    LAPACK's ``getrf`` reports it); ``piv[k]`` is the row swapped with row ``k``.
    """
    n = a.shape[0]
    sign = 1
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                big, p = abs(a[i, k]), i
        piv[k] = p
        if big == 0.0:
            return 0
        if p != k:
            sign = -sign
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
        if a[k, k] < 0.0:
            sign = -sign
        inv = 1.0 / a[k, k]
        for i in range(k + 1, n):
            f = a[i, k] * inv
            a[i, k] = f
            if f != 0.0:
                for j in range(k + 1, n):
                    a[i, j] -= f * a[k, j]
    return sign


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def lu_solve(a, piv, b):
    """Solve ``a y = b`` in place in the vector ``b`` from the factors of :func:`lu_factor`."""
    n = a.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= a[i, j] * b[j]
        b[i] = acc
    for i in range(n - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, n):
            acc -= a[i, j] * b[j]
        b[i] = acc / a[i, i]
