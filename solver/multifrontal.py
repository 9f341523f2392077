r"""Sparse :math:`LDL^H` of a Hermitian matrix by groups of unknowns: a supernodal multifrontal
factorisation.

The interface problem of an assembly (:mod:`solver.interface`) is sparse at the level of the
joints, not of single unknowns. Every row and every unknown belongs to one *group*: a joint's
load unknowns with its residual and constraint rows, a junction corner's forces with its
constraint rows, a plate's measurement residuals. Two groups are coupled when they see a
common plate. That graph is the plate grid's, so its separators are lines of joints; the
variable-level orderings of a general sparse LU (COLAMD) allow for any row interchange and
must separate along the wider graph of joints two plates apart (``bench/bench_interface.py``).

This module eliminates whole groups, in the order of a minimum-degree ordering of the group
graph weighted by the group sizes, with dense LAPACK kernels on each front:

.. math::
    F_{11}[p, p] = LDL^H,\quad Z = L^{-1}F_{12}[p],\quad M = D^{-1}Z,\quad
    C = F_{22} - Z^HM,

where :math:`F_{11}` is the square block of the group's own rows and unknowns (after the
updates of the groups eliminated before it), :math:`F_{12} = F_{21}^H` its coupling to the
groups it is connected to after fill, :math:`p` the symmetric interchanges and :math:`D` the
1 x 1 and 2 x 2 blocks of the Bunch–Kaufman factorisation of :math:`F_{11}` (LAPACK's
``hetrf``, its factor put in standard form by ``syconv``), and :math:`C` the contribution
passed to its parent in the elimination tree (extend-add). Chains of groups with nested
structure are merged into one front (fundamental supernodes). Interchanges stay inside
:math:`F_{11}` (restricted pivoting): the caller must make each group's block nonsingular by
construction — in the interface problem a group holds as many rows as unknowns, and its block
is the joint's compliance to its own loads — and must check the backward error of the result.
:class:`GroupPivotError` is raised when a block is exactly singular.

**Why symmetric pivoting.** Every front and every :math:`C` is Hermitian, so only the lower
triangles are computed and added: the product :math:`Z^HM`, the largest cost, costs 56 % of a
full one, and one triangular solve replaces LU's two. With symmetric interchanges the
rounding error of :math:`C` is bounded by the symmetric :math:`|Z|^H|D^{-1}||Z|`; with LU's
row interchanges :math:`|L_{21}||U_{12}|` is not symmetric, and completing :math:`C` from its
lower triangle raised the normwise backward error from 5e-17 to 1.1e-14 on a four-plate
system. Measured on the 10 x 10 grid's interface problems (one BLAS thread): 1e4 and 1.4e4
variables factorised in 0.73 s and 1.6 s against 0.9 s and 2.0 s with LU, backward errors
1.3e-17 and 1.4e-17 against 6e-17, and 6.6e6 factor entries kept against 1.08e7 (LU kept
both triangles of the coupling).

**Fronts hold the variables they touch.** The groups coupled to a front after fill are
coupled through some of their variables only: a joint's loads act on one or two plates, and a
small group (a junction corner's forces) touches a few of its neighbours' rows. A variable of
a later group that none of the front's entries and none of its children's contributions hold
has zero rows in :math:`F_{21}` and :math:`F_{22}`, and they stay zero through the update, so
each front holds only the others (:func:`_held_variables`). On the augmented problem of
``cases/box_with_wall.toml`` (4118 variables, 42 groups) the Schur products fall from
4.7e9 to 3.5e9 multiply-adds (a corner's front from 904 coupled variables to 176) and the
factorisation from 1.5-1.7 s to 1.2-1.3 s; on the 10 x 10 grid's (12008) from 2.3e9 to 1.9e9,
in the same time within the noise (2026-11-28, alternating runs).

**Memory.** The matrix is read from one entry of each conjugate pair, and its entries are
freed front by front as they are assembled when the caller hands it over. Each front is held
as :math:`F_{11}` (in Fortran order, factorised in place), :math:`F_{21}` and :math:`F_{22}`
(which becomes the contribution to the parent without a copy), and :math:`L` is kept in
rectangular full packed form (LAPACK's ``trttf``; ``tfsm`` solves with it as fast as
``trsm``): its triangle only. On the same two problems: 5.4e6 and 1.03e7 entries kept
against 6.6e6 and 1.25e7, in the same time and with the same backward errors.
"""

from __future__ import annotations

import heapq
from collections.abc import Sequence

import numpy as np
import scipy.sparse
from numpy.typing import ArrayLike
from scipy.linalg.blas import ztrsm
from scipy.linalg.lapack import zhetrf, zsyconv, ztfsm, ztrttf

from solver.errors import GroupPivotError

__all__ = ["GroupedLDL", "group_graph", "minimum_degree_order"]

# Row panels of a Schur complement's lower triangle: eight of at least 64 rows keep every
# product large enough for the BLAS's speed and cost 56 % of the full product.
PANELS = 8
PANEL_ROWS = 64
# Workspace of zhetrf per row: with less than its block size (64) times the rows it falls back
# to the unblocked algorithm, seven times slower on a front of 1400 rows.
HETRF_WORK = 64


def group_graph(row_groups: np.ndarray, col_groups: np.ndarray,
                n_groups: int) -> scipy.sparse.csr_matrix:
    """Adjacency (CSR, symmetric, no diagonal) of the groups coupled by a matrix's entries,
    given the groups of each entry's row and column. The distinct pairs are found by one sort
    of their codes: a sparse matrix built from every entry would sum millions of duplicates
    (0.3 s against 0.06 s for the 3.4e6 entries of the 10 x 10 grid's enriched problem)."""
    codes = np.unique(row_groups.astype(np.int64) * n_groups + col_groups)
    a, b = np.divmod(codes, n_groups)
    off = a != b
    a, b = np.concatenate([a[off], b[off]]), np.concatenate([b[off], a[off]])
    adjacency = scipy.sparse.csr_matrix((np.ones(len(a)), (a, b)), shape=(n_groups, n_groups))
    adjacency.data[:] = 1.0  # a pair present in both orders was summed
    return adjacency


def minimum_degree_order(adjacency: scipy.sparse.csr_matrix,
                         sizes: Sequence[int] | np.ndarray) -> np.ndarray:
    """Elimination order of the groups: repeatedly the group whose current neighbours hold the
    fewest unknowns (weighted minimum degree on the elimination graph; ties by index, so the
    order is reproducible).

    The weights are kept up to date as the cliques form: eliminating ``v`` joins its
    neighbours into a clique, so each of them loses ``v`` and gains the clique members it did
    not see yet, and only those are summed, not every neighbour again (the cliques of a large
    grid's separators hold hundreds of groups)."""
    n = adjacency.shape[0]
    sizes = [int(size) for size in sizes]
    neighbours = [set(adjacency.indices[adjacency.indptr[v]:adjacency.indptr[v + 1]].tolist())
                  for v in range(n)]
    current = [sum(sizes[u] for u in neighbours[v]) for v in range(n)]
    heap = [(w, v) for v, w in enumerate(current)]
    heapq.heapify(heap)
    eliminated = np.zeros(n, dtype=bool)
    order = []
    while heap:
        w, v = heapq.heappop(heap)
        if eliminated[v] or w != current[v]:
            continue
        eliminated[v] = True
        order.append(v)
        clique = neighbours[v]
        for u in clique:
            gained = clique - neighbours[u] - {u}
            neighbours[u] |= gained
            neighbours[u].discard(v)
            current[u] += sum(sizes[x] for x in gained) - sizes[v]
            heapq.heappush(heap, (current[u], u))
        neighbours[v] = set()
    return np.array(order, dtype=int)


def _elimination_structure(adjacency: scipy.sparse.csr_matrix,
                           order: np.ndarray) -> tuple[list[list[int]], list[list[int]]]:
    """Per group, the groups it is coupled to when it is eliminated (sorted by elimination
    position), and its children in the elimination tree."""
    n = len(order)
    position = np.empty(n, dtype=int)
    position[order] = np.arange(n)
    later = [None] * n
    children = [[] for _ in range(n)]
    for v in order:
        near = adjacency.indices[adjacency.indptr[v]:adjacency.indptr[v + 1]]
        coupled = set(near[position[near] > position[v]].tolist())
        for child in children[v]:
            coupled.update(later[child])
        coupled.discard(v)
        later[v] = sorted(coupled, key=position.__getitem__)
        if later[v]:
            children[later[v][0]].append(v)
    return later, children


def _supernodes(order: np.ndarray, later: Sequence[list[int]],
                children: Sequence[list[int]]) -> list[list[list[int]]]:
    """Fronts: ``(groups, later groups, child fronts)``; a group joins its only child's front
    when the child's structure is the group and the group's own (a fundamental supernode)."""
    fronts, front_of = [], {}
    for v in order:
        below = children[v]
        if len(below) == 1 and len(later[below[0]]) == len(later[v]) + 1:
            k = front_of[below[0]]
            fronts[k][0].append(v)
            fronts[k][1] = later[v]
        else:
            k = len(fronts)
            fronts.append([[v], later[v], [front_of[c] for c in below]])
        front_of[v] = k
    return fronts


def _extend_add(front: tuple[np.ndarray, np.ndarray, np.ndarray], at: np.ndarray,
                contribution: np.ndarray) -> None:
    """Add a child's ``contribution`` to a front stored by its lower part,
    ``front = (f11, f21, f22)`` (:math:`F_{11}`, :math:`F_{21}` and :math:`F_{22}`); ``at`` are
    the contribution's positions in the front. Entries above the diagonal that fall in
    :math:`F_{12}` are not needed and not added.

    The positions ``at`` increase (groups keep their elimination order in every front) and
    fall in runs, one per group or per several groups adjacent in both fronts; adding block
    by block moves memory at the speed of a copy, where one scatter of every entry took as
    long as the front's update product."""
    s = front[0].shape[0]
    breaks = np.flatnonzero((np.diff(at) != 1) | (at[1:] == s)) + 1
    starts = np.concatenate([[0], breaks])
    stops = np.concatenate([breaks, [len(at)]])
    if len(starts) > 24:  # many short runs: one scatter costs less than their pairs
        rows, cols = np.broadcast_arrays(at[:, None], at[None, :])
        lower = rows >= cols
        _scatter(front, rows[lower], cols[lower], contribution[lower], add=True)
        return
    spans = [(at[a], at[a] + b - a, a, b) for a, b in zip(starts, stops)]
    for i, (row, row_end, a, b) in enumerate(spans):
        for col, col_end, c, d in spans[:i + 1]:  # the lower triangle's blocks
            block, r, c0 = _block_of(front, row, col)
            block[r:r + b - a, c0:c0 + col_end - col] += contribution[a:b, c:d]


def _block_of(front: tuple[np.ndarray, np.ndarray, np.ndarray], row: int,
              col: int) -> tuple[np.ndarray, int, int]:
    """The block of ``front = (f11, f21, f22)`` holding position (row, col) on or below the
    diagonal, and the position's row and column in it."""
    s = front[0].shape[0]
    if col >= s:
        return front[2], row - s, col - s
    return (front[0], row, col) if row < s else (front[1], row - s, col)


def _scatter(front: tuple[np.ndarray, np.ndarray, np.ndarray], rows: np.ndarray, cols: np.ndarray,
             values: np.ndarray, add: bool = False) -> None:
    """Set (or add) ``values`` at the positions ``(rows, cols)``, ``rows >= cols``, of a front
    ``(f11, f21, f22)``; each position at most once."""
    f11, f21, f22 = front
    s = len(f11)
    for target, part, flat in (
            (f11.T, rows < s, lambda r, c: c * s + r),  # f11 is in Fortran order
            (f21, (rows >= s) & (cols < s), lambda r, c: (r - s) * s + c),
            (f22, cols >= s, lambda r, c: (r - s) * f22.shape[1] + c - s)):
        at = flat(rows[part], cols[part])
        if add:
            target.reshape(-1)[at] += values[part]
        else:
            target.reshape(-1)[at] = values[part]


def _symmetric_pivots(ipiv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""From LAPACK's ``hetrf`` interchanges (lower, 1-based; a 2 x 2 block marked by two equal
    negative entries): the permutation ``perm`` with :math:`F_{11}[perm][:, perm] = LDL^H` (the
    interchanges as ``hetrs2`` applies them) and the first index of each 2 x 2 block of D."""
    perm = np.arange(len(ipiv))
    pairs = []
    k = 0
    while k < len(ipiv):
        if ipiv[k] > 0:
            p = ipiv[k] - 1
            perm[k], perm[p] = perm[p], perm[k]
            k += 1
        else:
            p = -ipiv[k + 1] - 1
            perm[k + 1], perm[p] = perm[p], perm[k + 1]
            pairs.append(k)
            k += 2
    return perm, np.array(pairs, dtype=int)


class _BlockDiagonal:
    r""":math:`D^{-1}` of a Bunch–Kaufman factorisation, from its diagonal and, at the first index
    :math:`k` of each 2 x 2 block, its entry :math:`D_{k+1,k}` (Hermitian:
    :math:`D_{k,k+1} = \bar D_{k+1,k}`): the 1 x 1 blocks' reciprocals and each 2 x 2 block's
    explicit inverse, formed once and applied by every solve."""

    def __init__(self, diagonal: np.ndarray, below: np.ndarray, pairs: np.ndarray) -> None:
        self.pairs = pairs
        self.reciprocal = np.zeros(len(diagonal), dtype=complex)
        single = np.ones(len(diagonal), dtype=bool)
        single[pairs] = single[pairs + 1] = False
        self.reciprocal[single] = 1.0 / diagonal[single]
        a, b, c = diagonal[pairs], below[pairs], diagonal[pairs + 1]
        det = a * c - b * b.conj()
        # rows k and k + 1 of [[a, conj(b)], [b, c]]^-1
        self.inverse = np.stack([c, -b.conj(), -b, a]) / det

    def solve(self, z: np.ndarray) -> np.ndarray:
        r""":math:`D^{-1}z` for ``z`` of shape (s, k)."""
        out = self.reciprocal[:, None] * z
        if len(self.pairs):
            k = self.pairs
            first, second = z[k], z[k + 1]
            i11, i12, i21, i22 = (entry[:, None] for entry in self.inverse)
            out[k] = i11 * first + i12 * second
            out[k + 1] = i21 * first + i22 * second
        return out


def _subtract_lower(schur: np.ndarray, z: np.ndarray, m: np.ndarray) -> None:
    r"""``schur -= z^H @ m`` on and below the diagonal (and on some blocks above it), by panels
    of rows: the Schur complement :math:`Z^HD^{-1}Z` is Hermitian, so its lower triangle is all
    the elimination needs, and the panels cost :math:`\tfrac12(1 + 1/n_{panels})` of the full
    product."""
    n = schur.shape[0]
    panel = max(PANEL_ROWS, -(-n // PANELS))
    for start in range(0, n, panel):
        stop = min(start + panel, n)
        schur[start:stop, :stop] -= z[:, start:stop].conj().T @ m[:, :stop]


def _held_variables(later: Sequence[np.ndarray], holders: Sequence[np.ndarray],
                    touched: np.ndarray) -> np.ndarray:
    r"""The variables of the groups ``later`` (in their order) that a front holds entries of:
    those among its entries' rows and columns and its children's contributions
    (``holders``). The others' rows of :math:`F_{21}` and :math:`F_{22}` are zero, and stay
    zero through the update :math:`F_{22} - Z^HM` (a zero row of :math:`F_{21}` is a zero
    column of :math:`Z`), so the front leaves them out. Each later group keeps at least one
    variable (it is coupled through an entry, or through a child that kept one of it), so a
    front with later groups passes a contribution up. ``touched`` is a boolean work array
    over all variables, all False, and left so."""
    if not later:
        return np.zeros(0, dtype=int)
    candidates = np.concatenate(later)
    for held in holders:
        touched[held] = True
    coupled = candidates[touched[candidates]]
    for held in holders:
        touched[held] = False
    return coupled


class GroupedLDL:
    r""":math:`LDL^H` factors of a sparse Hermitian matrix eliminated group by group (module
    docstring).

    Parameters
    ----------
    matrix : scipy.sparse matrix, shape (n, n), or a list holding one
        A Hermitian matrix by the entries of its lower triangle, or of any one of each pair
        :math:`(i, j)`, :math:`(j, i)`, or of both (the two are the same value). Given in a
        list, it is taken out of it: the factorisation then holds the only reference and
        frees the entries as the fronts consume them (on the 10 x 10 grid's enriched problem,
        45 MB less at the peak).
    groups : ndarray of int, shape (n,)
        Group of each variable (row and column), labels 0 .. n_groups - 1.
    """

    def __init__(self, matrix: scipy.sparse.spmatrix | list[scipy.sparse.spmatrix],
                 groups: ArrayLike) -> None:
        matrix = (matrix.pop() if isinstance(matrix, list) else matrix).tocoo(copy=False)
        n = matrix.shape[0]
        groups = np.asarray(groups)
        n_groups = int(groups.max()) + 1 if n else 0
        by_group = np.argsort(groups, kind="stable")
        members = np.split(by_group, np.cumsum(np.bincount(groups, minlength=n_groups))[:-1])
        # the smallest integer type: gathers over millions of entries and the sort of them by
        # front (a radix sort up to 16 bits) run several times faster than on int64
        label = np.min_scalar_type(n_groups)
        row_groups = groups.astype(label)[matrix.row]
        col_groups = groups.astype(label)[matrix.col]
        adjacency = group_graph(row_groups, col_groups, n_groups)
        order = minimum_degree_order(adjacency, [len(m) for m in members])
        later, children = _elimination_structure(adjacency, order)
        fronts = _supernodes(order, later, children)
        front_of_group = np.empty(n_groups, dtype=np.min_scalar_type(len(fronts)))
        for k, (own, _, _) in enumerate(fronts):
            front_of_group[own] = k
        # each entry is assembled in the front of the first of its two groups to be eliminated
        first = np.minimum(front_of_group[row_groups], front_of_group[col_groups])
        del row_groups, col_groups
        by_front = np.argsort(first, kind="stable")
        bounds = np.searchsorted(first[by_front], np.arange(len(fronts) + 1))
        del first
        # each front's entries apart, freed once assembled
        pieces = [(matrix.row[part], matrix.col[part], matrix.data[part])
                  for part in np.split(by_front, bounds[1:-1])]
        del matrix, by_front

        self.factors = []  # per front: own, coupled, L packed, D^-1, perm, M = D^-1 L^-1 F12[perm]
        local = np.empty(n, dtype=int)
        touched = np.zeros(n, dtype=bool)
        contributions = {}
        for k, (own_groups, later_groups, child_fronts) in enumerate(fronts):
            own = np.concatenate([members[g] for g in own_groups])
            coupled = _held_variables(
                [members[g] for g in later_groups],
                [pieces[k][0], pieces[k][1]] + [contributions[c][0] for c in child_fronts],
                touched)
            index = np.concatenate([own, coupled])
            s, size = len(own), len(index)
            local[index] = np.arange(size)
            # the front by its lower part: F11 (in Fortran order, factorised in place), F21
            # and F22, which becomes the contribution to its parent without a copy
            front = (np.zeros((s, s), dtype=complex, order="F"),
                     np.zeros((size - s, s), dtype=complex),
                     np.zeros((size - s, size - s), dtype=complex))
            rows, cols, values = pieces[k]
            pieces[k] = None
            rows, cols = local[rows], local[cols]
            upper = rows < cols  # stored as its conjugate partner
            rows[upper], cols[upper] = cols[upper], rows[upper]
            np.conjugate(values, out=values, where=upper)
            _scatter(front, rows, cols, values)
            del rows, cols, values, upper
            for child in child_fronts:
                child_index, contribution = contributions.pop(child)
                _extend_add(front, local[child_index], contribution)
                del contribution  # before the next one, or the factorisation, is allocated
            f11, f21, rest = front
            del front
            f11, ipiv, info = zhetrf(f11, lower=1, lwork=HETRF_WORK * max(s, 1), overwrite_a=1)
            if info > 0:
                raise GroupPivotError(f"the pivot block of groups {own_groups} is singular")
            lower, below, _ = zsyconv(f11, ipiv, lower=1, way=0, overwrite_a=1)
            perm, pairs = _symmetric_pivots(ipiv)
            diagonal = _BlockDiagonal(np.diagonal(lower).real.copy(), below, pairs)
            m = np.zeros((s, 0), dtype=complex)
            if size > s:
                coupling = f21[:, perm]  # F12[perm] = F21[:, perm]^H
                np.conjugate(coupling, out=coupling)
                z = ztrsm(1.0, lower, coupling.T, lower=1, diag=1, overwrite_b=1)
                del coupling
                m = diagonal.solve(z)
                _subtract_lower(rest, z, m)
                del z
                contributions[k] = (coupled, rest)
            # L in rectangular full packed form: its triangle only, half the square's memory
            packed = ztrttf(lower, transr="N", uplo="L")[0]
            del f11, lower, f21, rest
            self.factors.append((own, coupled, packed, diagonal, perm, m))

    @property
    def nnz(self) -> int:
        """Stored entries of the factors."""
        return sum(packed.size + m.size for _, _, packed, _, _, m in self.factors)

    def solve(self, rhs: ArrayLike) -> np.ndarray:
        r""":math:`A^{-1}` ``rhs`` for ``rhs`` of shape (n,) or (n, k): front by front,
        :math:`y = L^{-1}b_{own}[perm]`, :math:`b_{coupled} \mathrel{-}= M^Hy`,
        :math:`y \leftarrow D^{-1}y`; then from the root,
        :math:`x_{own}[perm] = L^{-H}(y - Mx_{coupled})`."""
        x = _columns(rhs)
        for own, coupled, packed, diagonal, perm, m in self.factors:
            y = ztfsm(1.0, packed, x[own[perm]], transr="N", uplo="L", diag="U")
            if len(coupled):
                x[coupled] -= m.conj().T @ y
            x[own[perm]] = diagonal.solve(y)
        for own, coupled, packed, _, perm, m in reversed(self.factors):
            y = x[own[perm]]
            if len(coupled):
                y = y - m @ x[coupled]
            x[own[perm]] = ztfsm(1.0, packed, y, transr="N", uplo="L", trans="C", diag="U")
        return x[:, 0] if np.ndim(rhs) == 1 else x


def _columns(rhs: ArrayLike) -> np.ndarray:
    """A complex copy of ``rhs`` with one column per right-hand side."""
    x = np.array(rhs, dtype=complex)
    return x[:, None] if x.ndim == 1 else x
