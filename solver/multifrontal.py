r"""Sparse LU by groups of unknowns: a supernodal multifrontal factorisation.

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
    P_kF_{11} = L_{11}U_{11},\quad U_{12} = L_{11}^{-1}P_kF_{12},\quad
    L_{21} = F_{21}U_{11}^{-1},\quad C = F_{22} - L_{21}U_{12},

where :math:`F_{11}` is the square block of the group's own rows and unknowns (after the
updates of the groups eliminated before it), :math:`F_{12}, F_{21}` its coupling to the groups
it is connected to after fill, and :math:`C` the contribution passed to its parent in the
elimination tree (extend-add). Chains of groups with nested structure are merged into one
front (fundamental supernodes). Row interchanges stay inside :math:`F_{11}` (restricted
pivoting): the caller must make each group's block nonsingular by construction — in the
interface problem a group holds as many rows as unknowns, and its block is the joint's
compliance to its own loads — and must check the backward error of the result.
:class:`GroupPivotError` is raised when a block is exactly singular.

The interface matrix is Hermitian, but its symmetry is not used: with row interchanges,
:math:`|L_{21}||U_{12}|` is not symmetric, and a :math:`C` computed below the diagonal only
and completed by symmetry (56 % of the product, the largest cost) raised the normwise
backward error from 5e-17 to 1.1e-14 on the four-plate floors' system and from 6e-17 to 7e-16
on the 10 x 10 grid, for 10 % of the factorisation's time. Using the symmetry safely needs
symmetric (Bunch–Kaufman) pivoting inside each group.
"""

from __future__ import annotations

import heapq

import numpy as np
import scipy.sparse
from scipy.linalg.blas import ztrsm
from scipy.linalg.lapack import zgetrf

__all__ = ["GroupPivotError", "GroupedLU", "group_graph", "minimum_degree_order"]


class GroupPivotError(np.linalg.LinAlgError):
    """A group's pivot block is singular: restricted pivoting cannot factorise the matrix."""


def group_graph(row_groups, col_groups, n_groups):
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


def minimum_degree_order(adjacency, sizes):
    """Elimination order of the groups: repeatedly the group whose current neighbours hold the
    fewest unknowns (weighted minimum degree on the elimination graph; ties by index, so the
    order is reproducible)."""
    n = adjacency.shape[0]
    neighbours = [set(adjacency.indices[adjacency.indptr[v]:adjacency.indptr[v + 1]].tolist())
                  for v in range(n)]

    def weight(v):
        return sum(sizes[u] for u in neighbours[v])

    current = [weight(v) for v in range(n)]
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
            neighbours[u] |= clique
            neighbours[u] -= {u, v}
        for u in clique:
            current[u] = weight(u)
            heapq.heappush(heap, (current[u], u))
        neighbours[v] = set()
    return np.array(order, dtype=int)


def _elimination_structure(adjacency, order):
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


def _supernodes(order, later, children):
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


def _extend_add(front, at, contribution):
    """``front[at][:, at] += contribution``, by blocks of consecutive positions.

    The positions ``at`` increase (groups keep their elimination order in every front) and
    fall in runs, one per group or per several groups adjacent in both fronts; adding block
    by block moves memory at the speed of a copy, where one scatter of every entry took as
    long as the front's update product."""
    breaks = np.flatnonzero(np.diff(at) != 1) + 1
    starts = np.concatenate([[0], breaks])
    stops = np.concatenate([breaks, [len(at)]])
    if len(starts) > 24:  # many short runs: one scatter costs less than their pairs
        flat = front.reshape(-1)
        flat[(at[:, None] * front.shape[1] + at[None, :]).ravel()] += contribution.ravel()
        return
    spans = [(at[a], at[a] + b - a, a, b) for a, b in zip(starts, stops)]
    for row, row_end, a, b in spans:
        for col, col_end, c, d in spans:
            front[row:row_end, col:col_end] += contribution[a:b, c:d]


def _permutation(pivots):
    """Row permutation of LAPACK's ``getrf`` interchanges (0-based)."""
    perm = np.arange(len(pivots))
    for i, p in enumerate(pivots):
        perm[i], perm[p] = perm[p], perm[i]
    return perm


class GroupedLU:
    r"""LU factors of a sparse complex matrix eliminated group by group (module docstring).

    Parameters
    ----------
    matrix : scipy.sparse matrix, shape (n, n)
        Structurally symmetric at the level of the groups.
    groups : ndarray of int, shape (n,)
        Group of each variable (row and column), labels 0 .. n_groups - 1.
    rhs : ndarray, shape (n,) or (n, k), optional
        Right-hand sides solved during the factorisation (:attr:`solution`): the lower factor
        is applied front by front and not kept, which saves about half the memory of the
        factors; such an object solves nothing else.
    """

    def __init__(self, matrix, groups, rhs=None):
        matrix = matrix.tocoo(copy=False)
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

        self.factors = []  # per front: own, coupled, lu, perm, l21 (None with rhs), u12
        self._lower_kept = rhs is None
        forward = None if rhs is None else _columns(rhs)
        local = np.empty(n, dtype=int)
        contributions = {}
        for k, (own_groups, later_groups, child_fronts) in enumerate(fronts):
            own = np.concatenate([members[g] for g in own_groups])
            coupled = (np.concatenate([members[g] for g in later_groups]) if later_groups
                       else np.zeros(0, dtype=int))
            index = np.concatenate([own, coupled])
            s, size = len(own), len(index)
            local[index] = np.arange(size)
            front = np.zeros((size, size), dtype=complex)
            flat = front.reshape(-1)
            entries = by_front[bounds[k]:bounds[k + 1]]
            flat[local[matrix.row[entries]] * size + local[matrix.col[entries]]] = \
                matrix.data[entries]
            for child in child_fronts:
                child_index, contribution = contributions.pop(child)
                _extend_add(front, local[child_index], contribution)
            lu, pivots, info = zgetrf(front[:s, :s], overwrite_a=True)
            if info > 0:
                raise GroupPivotError(f"the pivot block of groups {own_groups} is singular")
            perm = _permutation(pivots)
            u12 = l21 = np.zeros((0, 0), dtype=complex)
            if size > s:
                u12 = ztrsm(1.0, lu, front[perm, s:], lower=1, diag=1)
                l21 = ztrsm(1.0, lu, front[s:, :s], side=1, lower=0)
                # a compact copy, so that the front itself is freed before its parent's
                schur = l21 @ u12
                np.subtract(front[s:, s:], schur, out=schur)
                contributions[k] = (coupled, schur)
            if forward is not None:
                _forward_step(forward, own, coupled, lu, perm, l21)
                l21 = None
            self.factors.append((own, coupled, lu, perm, l21, u12))
        self.solution = None
        if forward is not None:
            self.solution = self._backward(forward)
            if np.ndim(rhs) == 1:
                self.solution = self.solution[:, 0]

    @property
    def nnz(self) -> int:
        """Stored entries of the factors."""
        return sum(lu.size + u12.size + (0 if l21 is None else l21.size)
                   for _, _, lu, _, l21, u12 in self.factors)

    def solve(self, rhs):
        """:math:`A^{-1}` ``rhs`` for ``rhs`` of shape (n,) or (n, k)."""
        if not self._lower_kept:
            raise RuntimeError("this factorisation kept no lower factor (made with rhs)")
        x = _columns(rhs)
        for own, coupled, lu, perm, l21, _ in self.factors:
            _forward_step(x, own, coupled, lu, perm, l21)
        x = self._backward(x)
        return x[:, 0] if np.ndim(rhs) == 1 else x

    def _backward(self, x):
        """:math:`U^{-1}x` in place, front by front from the root."""
        for own, coupled, lu, _, _, u12 in reversed(self.factors):
            y = x[own]
            if len(coupled):
                y = y - u12 @ x[coupled]
            x[own] = ztrsm(1.0, lu, y, lower=0)
        return x


def _columns(rhs):
    """A complex copy of ``rhs`` with one column per right-hand side."""
    x = np.array(rhs, dtype=complex)
    return x[:, None] if x.ndim == 1 else x


def _forward_step(x, own, coupled, lu, perm, l21):
    r"""One front of :math:`L^{-1}x` in place: :math:`y = L_{11}^{-1}P x_{own}`,
    :math:`x_{coupled} \mathrel{-}= L_{21}y`."""
    y = ztrsm(1.0, lu, x[own][perm], lower=1, diag=1)
    x[own] = y
    if len(coupled):
        x[coupled] -= l21 @ y
