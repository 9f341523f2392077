r"""The dense solve of a plate's VTCR system (bending or in-plane): a truncated rank-revealing
factorisation, because a plate's rays are a redundant frame (``docs/method.md`` section 9.1,
``docs/accuracy.md`` section 6).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.linalg

__all__ = ["RANK_TOLERANCE", "MEMBRANE_RANK_TOLERANCE", "factorise_dense", "solve_dense"]


RANK_TOLERANCE = 1e-14
r"""Pivots of a plate's column-equilibrated VTCR matrix below this fraction of the largest are
discarded by :func:`factorise_dense`: the matrix's entries are quadrature sums whose rounding
is about this size, so those directions are not determined by them. 1e-12 to 1e-16 were
measured on the panels, the corner, Navier and the four plates (docs/method.md section 10.4):
larger values lose accuracy, smaller ones move round-off-level figures both ways."""

MEMBRANE_RANK_TOLERANCE = 1e-16
r""":data:`RANK_TOLERANCE` of a plate's in-plane (membrane) VTCR matrix. The in-plane
matrices of a moving line's members have a few pivots between 1e-16 and 1e-14 of the largest
(3 to 10 of 92 to 152 on ``cases/stiffened_panel.toml`` at 257 Hz and resolution 1.25), and
the directions they carry count: cut at 1e-14, a plate whose in-plane field is weak beside
what the line's loads excite was off by its own size. On ``cases/stiffened_panel.toml``
against independent finite elements (``bench/bench_panel.py``) the far bay B4 at 257 Hz and
resolution 1.25 was 1.8e-1 off (its neighbours 2e-2 to 8e-2), at 1e-16 1.8e-3 (every plate
within 5.2e-3); at 184.8 Hz 1.1e-3 and 5.5e-4 on the worst plate; at 1.5 the same; from
2.25 on 1.2 to 2.4 times closer (257 Hz, resolution 3.4: 3.4e-4 and 1.4e-4), never further.
The T junction of ``tests/test_held_ends.py`` (``bench/bench_held_counts.py``) at 1 kHz and
resolutions 1.5, 2.25, 3.4: 9.3e-5, 1.2e-4, 5.5e-5 and 3.1e-5, 6.2e-5, 4.8e-5; at 300 Hz,
where its interface system is ill-conditioned (``docs/method.md`` section 10.4, *The count*),
3.2e-4, 8.0e-4, 2.9e-3 and 3.3e-4, 1.2e-3, 9.0e-4. ``cases/box_with_wall.toml`` against its
finite elements (``bench/bench_box.py``, resolutions 1.5 and 2.25): the same to two digits, and
so are its estimates. At resolution 1 the in-plane fields of the L fold, U channel and T
junction of ``tests/test_moving_lines.py`` against their exact solutions (1 and 3 kHz) are the
same within 10 %; at 1.5 closer (the T junction at 300 Hz 2.9e-6 against 6.3e-6, the L fold
at 1 kHz 9.1e-7 against 5.6e-6) but for the U channel at 1 kHz, 1.2e-5 against 1.7e-6 (its
``w`` 2.4e-7 against 4.4e-8), and the error estimate of ``(u, v)`` at 1.5 now 1.00 to 1.33 times
the error where it read up to 35 (the L fold at 3 kHz, ``bench/bench_estimate_moving.py``).
0 (every pivot kept) gave the same as 1e-16 on the panel at 1.25 and 1.5.

The bending matrices keep 1e-14. At 1e-16 (on the moving lines' members only) the fields at
resolution 1.5 and above gain (the L fold with fixed ends at 1 kHz, ``(u, v)`` 5.0e-5 instead
of 2.6e-4; the panel's T1 at 257 Hz, ``w`` 2.8e-6 instead of 3.2e-5), but at resolution 1,
where the cut acts as a regularisation, they lose: against the exact solutions the L fold at 3
kHz is 8.2e-3 off in ``w`` instead of 1.3e-3, the T junction at 1 kHz 3.9e-3 instead of 7.1e-4,
the U channel at 3 kHz 2.9e-3 instead of 1.3e-3; and the held panel at 600 Hz and resolution
1.25 (all its plates at 1e-16) 6.8e-6 instead of 1.7e-6."""


def factorise_dense(matrix: np.ndarray, tolerance: float | None = None
                    ) -> tuple[Callable[[np.ndarray], np.ndarray], float]:
    r"""Truncated rank-revealing factorisation of a plate's VTCR matrix, and its reciprocal
    condition estimate.

    With :math:`E` the column equilibration (unit largest entry per column) and QR with column
    pivoting (LAPACK ``geqp3``), :math:`KEP = QR`, :math:`|R_{11}|\ge|R_{22}|\ge\dots`; the
    rank :math:`r` counts the pivots :math:`|R_{ii}| > \epsilon_r|R_{11}|` (``tolerance``,
    :data:`RANK_TOLERANCE` unless given: :data:`MEMBRANE_RANK_TOLERANCE` for in-plane
    matrices), and

    .. math:: x = EP\begin{bmatrix}R_{[r]}^{-1}Q_{[r]}^Hb\\ 0\end{bmatrix}

    with :math:`R_{[r]}`, :math:`Q_{[r]}` the leading :math:`r` rows and columns: the least-squares
    solution on the :math:`r` rays the pivoting chose, the others at zero amplitude.

    Why not LU: from resolution 1.5 on, a plate's rays are a redundant frame (0.4 x 0.5 m,
    1 mm at 2500 Hz: rank 366 of 480 rays at 1.5, 382 of 712 at 2.25). LU still solves, but
    adds to each solution a component along the near-null directions, as large as
    :math:`\epsilon\,\mathrm{cond}\,|b|` in coefficients, whose field error is about
    :math:`\epsilon|K||x|`. One load hides it (a single plate stays at 1e-10 to 10 kHz); the
    transfer operator :math:`T = K^{-1}B` of an assembly is solved load function by load
    function and summed by the interface unknowns, and there the coefficients of the sum were
    5e5 times those of one solve with the summed load: 1.2e-3 against 3.6e-9 for the same
    loads, and the stiffened panel's error grew with the rays (``docs/accuracy.md``, section
    6). Truncated, the coefficients stay bounded by :math:`|b|/(\epsilon_r|R_{11}|)` and the
    two routes agree. Normal equations are never formed.

    Returns
    -------
    solve : callable
        ``solve(rhs)`` for ``rhs`` of shape (n,) or (n, m).
    rcond : float
        Reciprocal condition estimate of the system solved, :math:`R_{[r]}` (LAPACK ``trcon``,
        1-norm): 1e-16 to 1e-15 where the whole equilibrated matrix's is 1e-21 to 1e-19.
    """
    n_rows, n_columns = matrix.shape
    scale = 1.0 / np.maximum(np.abs(matrix).max(axis=0), np.finfo(float).tiny)
    # mode "raw" keeps R in the upper triangle and the Householder reflectors of Q below it:
    # Q^H b is applied from them (LAPACK unmqr), since forming Q would cost about as much as
    # the factorisation itself; trcon and the triangular solve read the upper triangle only
    (factors, tau), _, pivots = scipy.linalg.qr(matrix * scale, mode="raw", pivoting=True,
                                                check_finite=False)
    pivot_sizes = np.abs(np.diag(factors))
    tolerance = RANK_TOLERANCE if tolerance is None else tolerance
    rank = int(np.count_nonzero(pivot_sizes > tolerance * pivot_sizes[0]))
    kept, triangle = pivots[:rank], factors[:rank, :rank]
    trcon, unmqr = scipy.linalg.get_lapack_funcs(("trcon", "unmqr"), (factors,))
    rcond, _ = trcon(triangle, norm="1")

    def solve(rhs: np.ndarray) -> np.ndarray:
        columns = np.array(np.reshape(rhs, (n_rows, -1)), dtype=complex, order="F")
        projected, _, _ = unmqr("L", "C", factors, tau, columns, overwrite_c=True,
                                lwork=max(1, 64 * columns.shape[1]))
        amplitudes = scipy.linalg.solve_triangular(triangle, projected[:rank],
                                                   check_finite=False)
        x = np.zeros((n_columns, columns.shape[1]), dtype=complex)
        x[kept] = amplitudes * scale[kept, None]
        return x.reshape((n_columns,) + np.shape(rhs)[1:])

    return solve, float(rcond)


def solve_dense(matrix: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, float]:
    """Truncated rank-revealing solve with column equilibration; returns ``(x, rcond)`` (see
    :func:`factorise_dense`)."""
    solve, rcond = factorise_dense(matrix)
    return solve(rhs), rcond
