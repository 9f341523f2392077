"""The LU factorisation by groups (solver.grouped_lu) against dense LAPACK, and its refusals.

The matrices are random with the structure of the interface systems: groups of rows and
unknowns as many as one another, blocks between groups coupled along a graph (a chain, as a
stiffened panel's weld lines; a grid, whose elimination makes fill), the rows and unknowns of
each group scattered through the numbering as the joints' are.
"""

import numpy as np
import pytest
import scipy.sparse

from solver import interface
from solver.errors import GroupPivotError
from solver.grouped_lu import GroupedLU


def _group_matrix(sizes, couplings, seed):
    """A random square matrix coupling group u to w for every (u, w) in ``couplings`` (both
    ways) and to itself, its rows and columns shuffled: ``(dense, row_groups, col_groups)``."""
    rng = np.random.default_rng(seed)
    n = sum(sizes)
    groups = np.repeat(np.arange(len(sizes)), sizes)
    row_groups, col_groups = rng.permutation(groups), rng.permutation(groups)
    dense = np.zeros((n, n), dtype=complex)
    pairs = [(v, v) for v in range(len(sizes))] + list(couplings) + [(w, u) for u, w in couplings]
    for u, w in pairs:
        rows, cols = np.flatnonzero(row_groups == u), np.flatnonzero(col_groups == w)
        block = rng.standard_normal((len(rows), len(cols))) + 1j * rng.standard_normal(
            (len(rows), len(cols)))
        block[rng.random(block.shape) < 0.3] = 0.0  # blocks need not be full
        dense[np.ix_(rows, cols)] = block
    return dense, row_groups, col_groups


def _grid_couplings(n):
    index = np.arange(n * n).reshape(n, n)
    return ([(index[i, j], index[i + 1, j]) for i in range(n - 1) for j in range(n)]
            + [(index[i, j], index[i, j + 1]) for i in range(n) for j in range(n - 1)])


@pytest.mark.parametrize("sizes, couplings", [
    ([7, 12, 5, 9, 11, 6], [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)]),
    ([4, 6, 5, 3, 8, 5, 4, 7, 6], _grid_couplings(3)),
], ids=["chain", "grid"])
def test_the_solution_is_dense_lapacks(sizes, couplings):
    """Solutions for a vector and for a second vector from the same factors agree with
    numpy.linalg.solve to 1e-11 of their size (measured 2e-15 to 5e-15: condition numbers 55
    and 72, and moderate growth under restricted pivoting)."""
    dense, row_groups, col_groups = _group_matrix(sizes, couplings, seed=3)
    rows, cols = np.nonzero(dense)
    factor = GroupedLU(rows, cols, dense[rows, cols], row_groups, col_groups)
    rng = np.random.default_rng(4)
    for _ in range(2):
        rhs = rng.standard_normal(len(dense)) + 1j * rng.standard_normal(len(dense))
        reference = np.linalg.solve(dense, rhs)
        error = np.abs(factor.solve(rhs) - reference).max() / np.abs(reference).max()
        assert error < 1e-11


def test_a_singular_group_block_is_refused_and_superlu_takes_over():
    """Two groups whose own blocks are zero while the whole matrix is not singular (the rows
    of each group act on the other's unknowns only): restricted pivoting cannot eliminate it.
    The factorisation says so, and the interface solve's grouped path declines."""
    dense, row_groups, col_groups = _group_matrix([5, 5], [(0, 1)], seed=5)
    for v in range(2):
        dense[np.ix_(row_groups == v, col_groups == v)] = 0.0
    rows, cols = np.nonzero(dense)
    with pytest.raises(GroupPivotError, match="singular"):
        GroupedLU(rows, cols, dense[rows, cols], row_groups, col_groups)
    rhs = np.ones(10, dtype=complex)
    assert interface._grouped_solution(scipy.sparse.csr_matrix(dense), rows, rhs, row_groups,
                                       col_groups) is None


def test_a_group_needs_as_many_rows_as_unknowns():
    dense, row_groups, col_groups = _group_matrix([4, 4], [(0, 1)], seed=6)
    row_groups = row_groups.copy()
    row_groups[np.flatnonzero(row_groups == 0)[0]] = 1
    rows, cols = np.nonzero(dense)
    with pytest.raises(GroupPivotError, match="as many rows as unknowns"):
        GroupedLU(rows, cols, dense[rows, cols], row_groups, col_groups)
