r"""Sparse LU of a square system by groups of rows and unknowns: the forward solve's interface
system (:func:`solver.interface._determined_solution`).

Every row and every unknown of that system belongs to a group: a joint's law samples and
constraints with its load unknowns, a junction corner's rows with its forces. A group holds as
many rows as unknowns, and two groups are coupled when they see a common plate. This module
eliminates whole groups, in the weighted minimum-degree order of the group graph
(:func:`solver.multifrontal.minimum_degree_order`), with dense LAPACK kernels on the blocks
:math:`A_{uv}` between groups:

.. math::
    A_{vv} = P_vL_vU_v,\qquad R_{vw} = A_{vv}^{-1}A_{vw},\qquad
    A_{uw} \leftarrow A_{uw} - A_{uv}R_{vw}

for the groups :math:`u, w` still coupled to :math:`v` when it is eliminated (the fill makes
new blocks). The solve is the block forward substitution :math:`y_v = A_{vv}^{-1}(b_v -
\sum_{v' < v}A_{vv'}y_{v'})` and back substitution :math:`x_v = y_v - \sum_{w > v}R_{vw}x_w`.

**Why.** SuperLU orders single unknowns (COLAMD) and finds its dense blocks itself; the
interface system is dense between groups and sparse at their level. Measured on forward
solves (one BLAS thread, the whole square solve, ``bench/bench_square_solve.py``): a 12-bay
moving-line panel at 2500 Hz, 4472 unknowns in 11 groups along a chain, 0.44 s against
SuperLU's 1.90 s; the 10 x 10 grid at 500 Hz (6624), 0.68 s against 1.06 s; 1.13 times
faster on the 4 x 4 and 6 x 6 grids (``docs/method.md`` section 7.4). Setting the blocks'
zero columns and rows apart (:data:`APART_FROM`) took the panels' factorisations 1.2 to 1.5
times faster again (2026-11-28, A/B in one session), and the held-line panel (24 bays at 2500
Hz, 4071 unknowns), which SuperLU solved faster before, to 0.13 s against its 0.15 s.

**Pivoting.** Interchanges stay inside each group's block (restricted pivoting): the block
must be nonsingular, as it is by construction (a joint's laws and constraints on its own
loads, as many as those: its compliance), and :class:`solver.errors.GroupPivotError` is raised
when one is exactly singular. The growth of the updates is not bounded as partial pivoting
over all rows would bound it: the caller refines the solution once and checks its backward
error (measured: 9e-15 before the refinement on the 12-bay panel, 2e-17 after, SuperLU's
level).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg.lapack import zgetrf, zgetrs

from solver.errors import GroupPivotError
from solver.multifrontal import group_graph, minimum_degree_order

__all__ = ["GroupedLU"]


def _local_positions(groups: np.ndarray, n_groups: int) -> tuple[np.ndarray, np.ndarray]:
    """Each index's position within its group (in index order) and the indices of each group,
    concatenated group by group: ``(local, members)``."""
    members = np.argsort(groups, kind="stable")
    starts = np.concatenate([[0], np.cumsum(np.bincount(groups, minlength=n_groups))])
    local = np.empty(len(groups), dtype=int)
    local[members] = np.arange(len(groups)) - starts[groups[members]]
    return local, members


APART_FROM = 128
"""Groups of this many unknowns or more have their blocks' zero columns and rows set apart when
they are eliminated (:meth:`GroupedLU._eliminate`). Indexing costs per entry what the products
save per entry and per unknown of the group: a moving-line panel's groups (376 to 432
unknowns) gain, a grid's (tens) lose (the 10 x 10 grid at 500 Hz took 1.9 s instead of 1.1 s
with every group's blocks set apart)."""

SPARSE_SIDE = 0.75
"""A block's columns (rows) are set apart when at most this fraction of them holds entries;
else the block is used whole, as indexing a few zeros away costs more than multiplying
them."""


def _held(block: np.ndarray, axis: int) -> np.ndarray | slice:
    """The indices of the columns (``axis=0``) or rows (``axis=1``) of ``block`` that hold
    entries, or every one (``slice(None)``) when more than :data:`SPARSE_SIDE` of them do."""
    held = np.flatnonzero(np.any(block, axis=axis))
    return held if len(held) <= SPARSE_SIDE * block.shape[1 - axis] else slice(None)


def _count(held: np.ndarray | slice, size: int) -> int:
    return size if isinstance(held, slice) else len(held)


def _subtract(target: np.ndarray, rows: np.ndarray | slice, columns: np.ndarray | slice,
              part: np.ndarray) -> None:
    """``target[rows, columns] -= part``, in place, rows and columns given by
    :func:`_held`."""
    if isinstance(rows, slice) and isinstance(columns, slice):
        target -= part
    else:
        target[np.ix_(np.arange(target.shape[0])[rows],
                      np.arange(target.shape[1])[columns])] -= part


class GroupedLU:
    """LU factorisation of a square sparse matrix by groups of rows and columns (module
    docstring).

    Parameters
    ----------
    rows, cols, values : ndarray
        The matrix's entries (COO, no entry given twice).
    row_groups, col_groups : ndarray of int, shape (n,)
        Group of each row and of each column, ``0 .. n_groups - 1``.

    Raises
    ------
    GroupPivotError
        When a group holds more rows than unknowns or fewer, or its block is exactly singular
        when it is eliminated.
    """

    def __init__(self, rows: np.ndarray, cols: np.ndarray, values: np.ndarray,
                 row_groups: np.ndarray, col_groups: np.ndarray) -> None:
        n_groups = int(max(row_groups.max(), col_groups.max())) + 1
        sizes = np.bincount(col_groups, minlength=n_groups)
        unequal = np.flatnonzero(np.bincount(row_groups, minlength=n_groups) != sizes)
        if len(unequal):
            raise GroupPivotError(f"group {unequal[0]} has not as many rows as unknowns")
        local_rows, row_members = _local_positions(row_groups, n_groups)
        local_cols, col_members = _local_positions(col_groups, n_groups)
        bounds = np.cumsum(sizes)[:-1]
        self._rows = np.split(row_members, bounds)
        self._cols = np.split(col_members, bounds)
        # the dense blocks between groups that hold entries: one sort of the entries by the
        # code of their pair of groups
        codes = row_groups[rows].astype(np.int64) * n_groups + col_groups[cols]
        by_code = np.argsort(codes, kind="stable")
        codes = codes[by_code]
        starts = np.flatnonzero(np.diff(codes)) + 1
        pairs = codes[np.concatenate([[0], starts])]
        blocks = {}
        for code, entries in zip(pairs.tolist(), np.split(by_code, starts)):
            u, w = divmod(code, n_groups)
            block = np.zeros(sizes[u] * sizes[w], dtype=complex)
            block[local_rows[rows[entries]] * sizes[w] + local_cols[cols[entries]]] = (
                values[entries])
            blocks[u, w] = block.reshape(sizes[u], sizes[w])
        u, w = np.divmod(pairs, n_groups)
        order = minimum_degree_order(group_graph(u, w, n_groups), sizes)
        self._steps = self._eliminate(blocks, order, sizes)

    @staticmethod
    def _eliminate(blocks: dict[tuple[int, int], np.ndarray], order: np.ndarray,
                   sizes: np.ndarray) -> list:
        """Eliminate the groups in ``order``; per group ``(v, (LU, pivots) of A_vv,
        {u: A_uv}, the later groups w coupled to it with the columns of A_vw that hold
        entries, [R_vw ...] on those columns side by side)``. ``blocks`` is consumed.

        The blocks right of a group are solved together, and each block below it updates
        them all by one product: LAPACK is called twice per group and once per coupled
        group, not once per pair of them (a grid's groups are small and many).

        Only the columns of :math:`A_{vw}` that hold entries are solved for (a column of
        zeros has :math:`R_{vw}` zero there), and only the rows of :math:`A_{uv}` that hold
        entries update :math:`A_{uw}`: a joint's loads act on one or two plates, so a
        block between two groups is zero in the columns of the loads the common plate does
        not carry (half of each forward block along a moving-line panel's chain, whose
        rows are half zero too)."""
        position = np.empty(len(order), dtype=int)
        position[order] = np.arange(len(order))
        right_of = {v: set() for v in order}  # w with a block A_vw, and u with A_uv
        left_of = {v: set() for v in order}
        for u, w in blocks:
            if u != w:
                right_of[u].add(w)
                left_of[w].add(u)
        steps = []
        for v in order:
            own = blocks.pop((v, v), None)
            lu, pivots, info = (None, None, 1) if own is None else zgetrf(own, overwrite_a=True)
            if info != 0:
                raise GroupPivotError(f"the block of group {v} is singular")
            right = [(w, blocks.pop((v, w))) for w in sorted(right_of[v])
                     if position[w] > position[v]]
            apart = sizes[v] >= APART_FROM
            later = [(w, _held(a_vw, 0) if apart else slice(None)) for w, a_vw in right]
            reduced = np.zeros((sizes[v], 0), dtype=complex)
            if later:
                reduced, _ = zgetrs(lu, pivots, np.hstack([a_vw[:, columns] for (_, a_vw), (
                    _, columns) in zip(right, later)]))
            bounds = np.cumsum([0] + [_count(columns, sizes[w]) for w, columns in later])
            coupling = {u: blocks.pop((u, v)) for u in sorted(left_of[v])
                        if position[u] > position[v]}
            for u, a_uv in coupling.items():
                rows = _held(a_uv, 1) if apart else slice(None)
                update = a_uv[rows] @ reduced
                for (w, columns), start, stop in zip(later, bounds[:-1], bounds[1:]):
                    part = update[:, start:stop]
                    if (u, w) in blocks:
                        _subtract(blocks[u, w], rows, columns, part)
                        continue
                    right_of[u].add(w)  # fill
                    left_of[w].add(u)
                    if isinstance(rows, slice) and isinstance(columns, slice):
                        blocks[u, w] = -part
                    else:
                        blocks[u, w] = np.zeros((sizes[u], sizes[w]), dtype=complex)
                        _subtract(blocks[u, w], rows, columns, part)
            steps.append((v, (lu, pivots), coupling, later, reduced))
        return steps

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """:math:`x = A^{-1}b` for ``rhs`` of shape (n,)."""
        remaining = [rhs[r].astype(complex) for r in self._rows]
        forward = {}
        for v, (lu, pivots), coupling, _, _ in self._steps:
            forward[v], _ = zgetrs(lu, pivots, remaining[v])
            for u, a_uv in coupling.items():
                remaining[u] -= a_uv @ forward[v]
        x = np.empty(len(rhs), dtype=complex)
        for v, _, _, later, reduced in reversed(self._steps):
            x_v = forward[v]
            if later:
                x_v = x_v - reduced @ np.concatenate([x[self._cols[w][columns]]
                                                      for w, columns in later])
            x[self._cols[v]] = x_v
        return x
