r"""Sparse solve of the interface problem of a jointed assembly, and its condensation.

Every interface problem of the substructured VTCR — the direct problem (r = 0), the modified
problem of the updating (r > 0), a synthetic experiment — is a constrained linear least-squares
problem in the interface unknowns :math:`S` (``docs/method.md`` sections 7.3 and 7.4):

.. math::
    \min_S \sum_b \|A_b S_{I_b} + a_b\|^2 \quad\text{subject to}\quad GS = g ,

where each *block* :math:`b` — the weighted residual samples of one joint channel, or the
weighted misfit at the measured points of one plate — acts only on the interface unknowns
:math:`I_b` that its plates see. The blocks are solved in augmented form, with their residuals
:math:`\rho_b = A_bS_{I_b} + a_b` as unknowns:

.. math::
    \begin{bmatrix} -I & A & 0\\ A^H & 0 & G^H\\ 0 & G & 0\end{bmatrix}
    \begin{bmatrix}\rho\\ S\\ \lambda\end{bmatrix} =
    \begin{bmatrix}-a\\ 0\\ g\end{bmatrix} ,

(eliminating :math:`\rho` gives the KKT system of the normal equations,
:math:`[A^HA\ G^H; G\ 0]`). The matrix is Hermitian, sparse, with
:math:`2\sum_b \mathrm{rows}_b|I_b| + 2\,\mathrm{nnz}(G)` entries besides the identity:
linear in the number of joints, where the Gram matrices :math:`A_b^HA_b` would be quadratic
in the size of each neighbourhood, and the condition number is that of :math:`A`, not its
square. Only its lower triangle (:math:`-I`, :math:`A^H` and :math:`G`) is stored. After a
symmetric equilibration it is factorised group by group: each joint's load
unknowns, residual rows and constraint rows form a group with as many rows as unknowns, whose
block is the joint's compliance to its own loads, and the groups are eliminated in a
minimum-degree order of the graph of groups that see a common plate, with symmetric
(Bunch–Kaufman) interchanges inside each group (:class:`solver.multifrontal.GroupedLDL`). The
general sparse LU with partial pivoting (SuperLU, ``scipy.sparse.linalg.splu``, COLAMD
ordering) must allow for interchanges between any rows, and its fill follows the wider graph
of joints two plates apart: on the 10 x 10 grid, 2.0e7 entries in 5.3 s against 1.1e7 in
1.0 s (the grouped LU then; 0.67 s and 5.4e6 entries now). SuperLU remains the path for small
systems, where it is faster, for groups with fewer rows than unknowns, and whenever the
grouped solution's backward error exceeds :data:`BACKWARD_ERROR`. ``bench/bench_interface.py``
compares the alternatives.

**Condensation on one joint** (:class:`JointCondensation`). While one joint's parameters
:math:`c` vary, only its residual rows change: its residual samples are
:math:`r(c) = y_L - c\,y_R` with :math:`y = PS + p` (:math:`P` the sampled load and kinematic
operators on the joint's :math:`n_f` load functions, weights :math:`W^{1/2}` folded in), and
its energy is :math:`y^HM(c)y` with the :math:`2n_f\times2n_f` matrix

.. math:: M(c) = \frac{\kappa}{2\,\mathrm{Re}\,c}\begin{bmatrix} I & -cI\\ -\bar cI & |c|^2I
          \end{bmatrix},\qquad \kappa = \alpha_\Gamma(1-r)/E_{ref}.

From the factorisation :math:`K_0` at :math:`c_0`, with :math:`X = K_0^{-1}P^H` (S-part; it
satisfies :math:`GX = 0`), :math:`Z = PX` (Hermitian, positive semidefinite) and
:math:`y_0 = PS_0 + p`, the Sherman–Morrison–Woodbury identity gives the minimiser at :math:`c`
as :math:`S = S_0 - X\,\Delta M\,y` with

.. math:: (I + Z\,\Delta M)\,y = y_0,\qquad \Delta M = M(c) - M(c_0),

and, because :math:`X` lies in the null space of :math:`G` (the first-order term vanishes at the
constrained minimum), the cost

.. math:: E(c) = E(c_0) + t^HZt + y^H\Delta M\,y,\qquad t = \Delta M\,y .

One evaluation is a dense solve of the size of the joint's residual samples (:math:`2n_f` per
channel, :class:`JointCondensation`): its cost does not depend on the size of the structure.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
from numpy.typing import ArrayLike

from solver.errors import GroupPivotError
from solver.multifrontal import GroupedLDL

__all__ = ["BACKWARD_ERROR", "GROUPED_MIN_SIZE", "Block", "InterfaceFactor", "factorise_interface",
           "JointCondensation", "backward_error", "hermitian_full", "residual_weight",
           "squared_norm"]

# Largest backward error accepted from the grouped factorisation, whose row interchanges stay
# inside each group: SuperLU's partial pivoting gives 1e-18 to 1e-16 on these systems, and so
# does the grouped one on every case and stiffness measured (four plates at log10 k = -3 to 12,
# the boxes, the stiffened panel, the 10 x 10 grid).
BACKWARD_ERROR = 1e-14
# Below this size of the augmented system SuperLU is faster (measured on the N x N grids and the
# cases: N = 3, 656 variables, 22 against 29 ms; N = 4, 1320, 91 against 87 ms; N = 8, 6216,
# 2.4 s against 1.0 s).
GROUPED_MIN_SIZE = 1500
# Above this fraction of filled entries, a forward solve's square system is factorised dense:
# the moving-line panel's (808 unknowns, 71 % filled) in 0.036 s against SuperLU's 0.052 s;
# the grids' (5 to 16 % filled) stay with SuperLU.
DENSE_FILL = 0.3


def residual_weight(c: complex, crossover: float = math.inf) -> float:
    r"""Weight :math:`g` of a joint channel's residual energy :math:`e^2 = g(c)\int|r|^2`.

    .. math:: g(c) = \frac{1}{2\max(\mathrm{Re}\,c,\ |c|^2/c_\times)} .

    Below the crossover :math:`c_\times` this is the constitutive-relation error in the energy
    norm, :math:`|r|^2/(2k)` (``docs/method.md`` section 6.3). Above it the residual is measured
    in compliance form, :math:`e^2 = \tfrac12c_\times|r/c|^2 = \tfrac12c_\times|[q] - \Lambda/c|^2`:
    the jump of a discretised near-rigid joint cannot fall below the discretisation floor of
    the continuity it approximates (1.6e-5 of the plates' rotations on ``two_plates.toml``),
    and the energy norm would multiply that floor by :math:`k` without bound (the floor of
    :math:`E_\Gamma^2` grew tenfold per decade of :math:`k` above :math:`10^8`). Both forms agree
    at :math:`|c| = c_\times` and :math:`g` is continuous in :math:`c`.
    """
    return 1.0 / (2.0 * max(c.real, abs(c) ** 2 / crossover))


@dataclass(frozen=True)
class Block:
    """Rows of the least-squares objective acting on a few interface unknowns.

    Attributes
    ----------
    index : ndarray of int, shape (m,)
        Interface unknowns the rows act on.
    matrix : ndarray of complex, shape (rows, m)
    offset : ndarray of complex, shape (rows,)
    group : int
        The group of unknowns its rows are eliminated with (:mod:`solver.multifrontal`): the
        joint whose residual they are; -1 for rows that form a group of their own.
    """

    index: np.ndarray
    matrix: np.ndarray
    offset: np.ndarray
    group: int = -1

    def residual(self, s: np.ndarray) -> np.ndarray:
        """:math:`A_bS_{I_b} + a_b` for interface unknowns ``s`` of shape (n_s,), or of shape
        (n_s, k) for k sets of them at once (one column each)."""
        product = self.matrix @ s[self.index]
        return product + (self.offset if product.ndim == 1 else self.offset[:, None])

    def scaled(self, factor: complex | np.ndarray) -> Block:
        """The Block with its rows multiplied by ``factor`` (a scalar or one value per row)."""
        factor = np.asarray(factor)
        return Block(self.index, (factor.T * self.matrix.T).T, factor * self.offset, self.group)

    def projected(self, projection: np.ndarray) -> Block:
        """The Block's rows replaced by ``projection`` of them (for instance on a joint's
        load functions, :func:`solver.joint_rules.load_function_projection`)."""
        return Block(self.index, projection @ self.matrix, projection @ self.offset, self.group)

    def constraint(self, group: int) -> Block:
        """The rows ``matrix S_I = -offset`` as a constraint Block of ``group``: the sign of
        :math:`GS = g` from a quantity :math:`AS_I + a` that must vanish."""
        return Block(self.index, self.matrix, -self.offset, group)

    @staticmethod
    def union(*blocks: Block) -> Block:
        """Sum of Blocks with as many rows as one another, as one Block over the union of their
        unknowns."""
        index = np.unique(np.concatenate([b.index for b in blocks]))
        matrix = np.zeros((blocks[0].matrix.shape[0], len(index)), dtype=complex)
        for b in blocks:
            matrix[:, np.searchsorted(index, b.index)] += b.matrix
        return Block(index, matrix, sum(b.offset for b in blocks))


def squared_norm(r: np.ndarray) -> float | np.ndarray:
    r""":math:`\|r\|^2` of a vector, or of each column of a matrix (an array of them)."""
    if np.ndim(r) == 1:
        return float(np.vdot(r, r).real)
    return np.einsum("ij,ij->j", r.conj(), r).real


def _augmented_matrix(n_s: int, blocks: Iterable[Block],
                      g_mat: scipy.sparse.spmatrix) -> tuple[scipy.sparse.coo_matrix, int]:
    """The lower triangle of the Hermitian augmented matrix ``[-I A 0; A^H 0 G^H; 0 G 0]`` in
    COO form (:func:`hermitian_full` completes it), and the number of residual rows."""
    rows, cols, vals = [], [], []
    start = 0
    for block in blocks:
        n_rows, m = block.matrix.shape
        rows.append(np.repeat(np.arange(start, start + n_rows, dtype=np.int32), m))
        cols.append(np.tile(block.index.astype(np.int32), n_rows))
        vals.append(block.matrix.ravel())
        start += n_rows
    n_rho = start
    a_rows = np.concatenate(rows) if rows else np.zeros(0, dtype=np.int32)
    a_cols = np.concatenate(cols) + n_rho if cols else np.zeros(0, dtype=np.int32)
    a_vals = np.concatenate(vals) if vals else np.zeros(0, dtype=complex)
    g = g_mat.tocoo()
    diag = np.arange(n_rho, dtype=np.int32)
    n = n_rho + n_s + g_mat.shape[0]
    lower = scipy.sparse.coo_matrix(
        (np.concatenate([-np.ones(n_rho), a_vals.conj(), g.data]),  # -I, A^H and G
         (np.concatenate([diag, a_cols, (g.row + n_rho + n_s).astype(np.int32)]),
          np.concatenate([diag, a_rows, (g.col + n_rho).astype(np.int32)]))),
        shape=(n, n), dtype=complex)
    return lower, n_rho


def _hermitian_product(lower: scipy.sparse.coo_matrix, x: ArrayLike) -> np.ndarray:
    """:math:`Hx` for the Hermitian :math:`H` whose lower triangle is ``lower`` (COO, each
    entry once)."""
    on = lower.row == lower.col
    diagonal = np.zeros(lower.shape[0], dtype=lower.dtype)
    diagonal[lower.row[on]] = lower.data[on]
    x = np.asarray(x)
    product = lower @ x + (lower.T @ x.conj()).conj()
    return product - diagonal.reshape((-1,) + (1,) * (x.ndim - 1)) * x


def hermitian_full(lower: scipy.sparse.coo_matrix) -> scipy.sparse.csc_matrix:
    """The whole Hermitian matrix (CSC) whose lower triangle is ``lower`` (COO)."""
    strict = lower.row != lower.col
    return scipy.sparse.coo_matrix(
        (np.concatenate([lower.data, lower.data[strict].conj()]),
         (np.concatenate([lower.row, lower.col[strict]]),
          np.concatenate([lower.col, lower.row[strict]]))), shape=lower.shape).tocsc()


@dataclass
class InterfaceFactor:
    """A factorised interface problem: its solution and solves with other right-hand sides.

    Attributes
    ----------
    lu : SuperLU or GroupedLDL or None
        The factorisation; None when it was not kept (``factorise_interface(keep=False)``).
    s : ndarray of complex, shape (n_s,)
        The minimiser.
    residuals : list of ndarray
        :math:`\\rho_b` of each block at the minimiser.
    block_rows : list of slice
        The rows of each block, in the order they were given, in the augmented system (its
        residual rows :math:`\\rho`): what a caller keeps of the solves without counting rows.
    """

    lu: object
    scale: np.ndarray
    n_rho: int
    n_s: int
    s: np.ndarray
    residuals: list
    constraint_rhs: np.ndarray
    block_rows: list

    def solve(self, rhs: ArrayLike) -> np.ndarray:
        """The whole augmented solution :math:`(\\rho, S, \\lambda)` for ``rhs`` (n_s, k) in
        the S rows, zero elsewhere."""
        rhs = np.asarray(rhs, dtype=complex).reshape(self.n_s, -1)
        full = np.zeros((len(self.scale), rhs.shape[1]), dtype=complex)
        full[self.n_rho:self.n_rho + self.n_s] = rhs
        return self.lu.solve(full * self.scale[:, None]) * self.scale[:, None]

    def solve_interface(self, rhs: ArrayLike) -> np.ndarray:
        """S-part of the augmented solve with ``rhs`` (n_s, k) in the S rows, zero elsewhere.

        This is :math:`[A^HA\\ G^H; G\\ 0]^{-1}[rhs; 0]` restricted to S.
        """
        return self.solve(rhs)[self.n_rho:self.n_rho + self.n_s].copy()

    def resolve(self, offsets: Iterable[Iterable[np.ndarray]]) -> np.ndarray:
        """Minimisers for other block offsets :math:`a_b` (same matrices, same constraints).

        Parameters
        ----------
        offsets : sequence of sequences of ndarray
            For each problem, the offsets of every block, in the order of the factorisation.

        Returns
        -------
        ndarray of complex, shape (len(offsets), n_s)
        """
        rhs = np.column_stack([
            np.concatenate([-np.concatenate(list(problem)), np.zeros(self.n_s, dtype=complex),
                            self.constraint_rhs]) for problem in offsets])
        x = self.lu.solve(rhs * self.scale[:, None]) * self.scale[:, None]
        return x[self.n_rho:self.n_rho + self.n_s].T

    @property
    def cost(self) -> float:
        """:math:`\\sum_b\\|\\rho_b\\|^2` at the minimiser."""
        return float(sum(np.vdot(r, r).real for r in self.residuals))


def factorise_interface(n_s: int, blocks: Sequence[Block],
                        constraints: tuple[scipy.sparse.spmatrix, ArrayLike],
                        groups: tuple[np.ndarray, np.ndarray] | None = None,
                        keep: bool = True) -> InterfaceFactor:
    """Factorise and solve :math:`\\min\\sum_b\\|A_bS_{I_b}+a_b\\|^2` s.t. :math:`GS = g`.

    Parameters
    ----------
    n_s : int
        Number of interface unknowns.
    blocks : sequence of Block
    constraints : (scipy.sparse matrix (n_g, n_s), ndarray (n_g,))
    groups : (ndarray (n_s,), ndarray (n_g,)) of int, optional
        Group of each interface unknown and constraint row (``Block.group`` gives the blocks'
        rows theirs). With them, a system of at least :data:`GROUPED_MIN_SIZE` variables is
        factorised group by group (:class:`solver.multifrontal.GroupedLDL`) when every group
        holds at least as many rows as unknowns, and its solution is kept if its backward
        error is below :data:`BACKWARD_ERROR`; otherwise, and without groups, by SuperLU.
    keep : bool
        Keep the factorisation for other right-hand sides (:meth:`InterfaceFactor.solve`,
        :meth:`InterfaceFactor.resolve`). Without, only the minimiser is wanted and the
        result's ``lu`` is None (the factors are freed on return).

    Returns
    -------
    InterfaceFactor
    """
    g_mat = scipy.sparse.csr_matrix(constraints[0])
    g_rhs = np.asarray(constraints[1], dtype=complex)
    if not keep and sum(len(b.offset) for b in blocks) + g_mat.shape[0] == n_s:
        return _minimiser(blocks, n_s, _determined_solution(n_s, blocks, g_mat, g_rhs), g_rhs)
    matrix, n_rho, scale = _equilibrated(n_s, blocks, g_mat)
    rhs = np.concatenate([-np.concatenate([b.offset for b in blocks]) if blocks
                          else np.zeros(0, dtype=complex), np.zeros(n_s, dtype=complex), g_rhs])
    scaled_rhs = rhs * scale
    lu, x = None, None
    variable_groups = (_variable_groups(blocks, n_rho, groups)
                       if groups is not None and matrix.shape[0] >= GROUPED_MIN_SIZE else None)
    if variable_groups is not None:
        holder = [matrix]  # the factorisation frees the entries as it goes
        del matrix
        try:
            lu = GroupedLDL(holder, variable_groups)
            x = lu.solve(scaled_rhs)
        except GroupPivotError:
            lu = None
        matrix = _equilibrated(n_s, blocks, g_mat)[0]  # again, for the check (0.05 s at most)
        if lu is not None and backward_error(matrix, x, scaled_rhs) > BACKWARD_ERROR:
            lu = None
    if lu is None:
        # The transfer operators of enriched Trefftz bases make this system as ill-conditioned
        # as the plate blocks (``docs/method.md`` section 9.1); LU with partial pivoting is
        # backward stable, and accuracy is judged on fields and energies.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.sparse.linalg.MatrixRankWarning)
            lu = scipy.sparse.linalg.splu(hermitian_full(matrix), permc_spec="COLAMD",
                                          diag_pivot_thresh=0.1)
        x = lu.solve(scaled_rhs)
    x = x * scale
    return _minimiser(blocks, n_s, x[n_rho:n_rho + n_s], g_rhs, lu if keep else None, scale)


def _minimiser(blocks: Sequence[Block], n_s: int, s: np.ndarray, g_rhs: np.ndarray,
               lu: object = None, scale: np.ndarray | None = None) -> InterfaceFactor:
    """The InterfaceFactor of the minimiser ``s``, with its factorisation if kept."""
    ends = np.cumsum([len(b.offset) for b in blocks], dtype=int)
    rows = [slice(int(end - len(b.offset)), int(end)) for b, end in zip(blocks, ends)]
    n_rho = int(ends[-1]) if len(blocks) else 0
    return InterfaceFactor(lu, scale, n_rho, n_s, s, [b.residual(s) for b in blocks], g_rhs, rows)


def _determined_solution(n_s: int, blocks: Sequence[Block], g_mat: scipy.sparse.csr_matrix,
                         g_rhs: np.ndarray) -> np.ndarray:
    r"""The minimiser of a problem with as many residual rows and constraints as unknowns: the
    solution of the square system

    .. math:: K S = \begin{bmatrix} A \\ G \end{bmatrix} S
              = \begin{bmatrix} -a \\ g \end{bmatrix},

    whose residuals vanish, equilibrated by rows and then columns and factorised with partial
    pivoting (backward stable, like the augmented system's factorisations): by LAPACK when more
    than :data:`DENSE_FILL` of its entries are filled, else by SuperLU.

    A forward solve is such a problem: every joint holds as many law samples and constraints
    as load unknowns (:func:`_variable_groups`), and only measurements add rows. :math:`K` has
    half the size of the augmented matrix :math:`[-I\ A\ 0;\ A^H\ 0\ G^H;\ 0\ G\ 0]`:
    on the moving-line stiffened panel at 2500 Hz (808 unknowns) the interface solve takes
    0.04 s against 0.17 s, on the 8 x 8 grid (3108) 0.22 s against 0.35 s
    (``docs/method.md`` section 7.4).
    """
    g_entries = g_mat.tocoo()
    n_rho = sum(len(b.offset) for b in blocks)
    starts = np.cumsum([0] + [len(b.offset) for b in blocks])
    rows = np.concatenate([np.repeat(np.arange(start, start + len(b.offset)), len(b.index))
                           for start, b in zip(starts, blocks)] + [g_entries.row + n_rho])
    cols = np.concatenate([np.tile(b.index, len(b.offset)) for b in blocks] + [g_entries.col])
    values = np.concatenate([b.matrix.ravel() for b in blocks] + [g_entries.data])
    rhs = np.concatenate([-b.offset for b in blocks] + [g_rhs])
    tiny = np.finfo(float).tiny
    if len(values) > DENSE_FILL * n_s ** 2:
        k_mat = np.zeros((n_s, n_s), dtype=complex)
        k_mat[rows, cols] = values
        row_scale = 1.0 / np.maximum(np.abs(k_mat).max(axis=1), tiny)
        k_mat *= row_scale[:, None]
        col_scale = 1.0 / np.maximum(np.abs(k_mat).max(axis=0), tiny)
        k_mat *= col_scale
        factors = scipy.linalg.lu_factor(k_mat, overwrite_a=True, check_finite=False)
        return col_scale * scipy.linalg.lu_solve(factors, rhs * row_scale, check_finite=False)
    k_mat = scipy.sparse.csr_matrix((values, (rows, cols)), shape=(n_s, n_s))
    row_scale = 1.0 / np.maximum(abs(k_mat).max(axis=1).toarray().ravel(), tiny)
    k_mat = scipy.sparse.diags(row_scale) @ k_mat
    col_scale = 1.0 / np.maximum(abs(k_mat).max(axis=0).toarray().ravel(), tiny)
    k_mat = (k_mat @ scipy.sparse.diags(col_scale)).tocsc()
    lu = scipy.sparse.linalg.splu(k_mat, permc_spec="COLAMD")
    return col_scale * lu.solve(rhs * row_scale)


def _equilibrated(n_s: int, blocks: Iterable[Block],
                  g_mat: scipy.sparse.spmatrix) -> tuple[scipy.sparse.coo_matrix, int, np.ndarray]:
    r"""The lower triangle of the augmented matrix scaled symmetrically, ``D H D``, with
    :math:`D_{ii} = (\max_j|H_{ij}|)^{-1/2}` (its rows mix residuals, energies per unit load
    and displacements), the number of residual rows and the scale D."""
    matrix, n_rho = _augmented_matrix(n_s, blocks, g_mat)
    row_max = np.zeros(matrix.shape[0])
    np.maximum.at(row_max, matrix.row, np.abs(matrix.data))
    np.maximum.at(row_max, matrix.col, np.abs(matrix.data))
    scale = 1.0 / np.sqrt(np.maximum(row_max, np.finfo(float).tiny))
    matrix.data *= scale[matrix.row] * scale[matrix.col]
    return matrix, n_rho, scale


def backward_error(lower: scipy.sparse.coo_matrix, x: np.ndarray, rhs: np.ndarray) -> float:
    r"""Normwise backward error :math:`\|Hx - b\|_\infty / (\|H\|_\infty\|x\|_\infty +
    \|b\|_\infty)` of a solution ``x`` of :math:`Hx = b`, :math:`H` Hermitian given by its
    lower triangle ``lower`` (COO)."""
    residual = _hermitian_product(lower, x) - rhs
    magnitude = np.abs(lower.data)
    off = np.where(lower.row != lower.col, magnitude, 0.0)
    norm = (np.bincount(lower.row, magnitude, lower.shape[0])
            + np.bincount(lower.col, off, lower.shape[0])).max()
    return float(np.max(np.abs(residual)) / (norm * np.max(np.abs(x)) + np.max(np.abs(rhs))))


def _variable_groups(blocks: Sequence[Block], n_rho: int,
                     groups: tuple[np.ndarray, np.ndarray]) -> np.ndarray | None:
    """Group of every variable of the augmented system — ``rho`` rows by their blocks, then
    S, then the multipliers — or None when a group holds fewer rows than unknowns (its pivot
    block would be singular: a joint without residual weight, say)."""
    unknown_groups, constraint_groups = groups
    sizes = [len(b.offset) for b in blocks]
    own = np.repeat(np.array([b.group for b in blocks], dtype=int), sizes)
    alone = own < 0  # rows of their own: a group per block
    first = max(unknown_groups.max(initial=-1), constraint_groups.max(initial=-1)) + 1
    own[alone] = first + np.repeat(np.arange(len(blocks)), sizes)[alone]
    labels = np.concatenate([own, unknown_groups, constraint_groups])
    _, labels = np.unique(labels, return_inverse=True)
    is_row = np.ones(len(labels), dtype=bool)
    is_row[n_rho:n_rho + len(unknown_groups)] = False
    rows = np.bincount(labels[is_row], minlength=labels.max() + 1)
    unknowns = np.bincount(labels[~is_row], minlength=labels.max() + 1)
    return labels if np.all(rows >= unknowns) else None


class JointCondensation:
    r"""The cost of the interface problem as a function of one joint's channel parameters.

    See the module docstring: built once from the factorisation at the current parameters
    :math:`c_0`, each :meth:`cost` is a dense solve of the size of the joint's residual samples.

    Each channel's load and kinematic samples are :math:`n_f` numbers each (the joint's
    residual on its load functions, :func:`solver.joint_rules.load_function_projection`), so a
    joint's dense solves are of size :math:`2n_f` per channel.

    Parameters
    ----------
    factor : InterfaceFactor
        Factorisation at the base parameters.
    channels : sequence of (Block, Block, float, complex, float)
        Per channel of the joint: its load samples :math:`W^{1/2}(LS + l)`, its kinematic
        samples :math:`W^{1/2}(RS + \rho)` (blocks over interface unknowns, unweighted by the
        channel parameter), the weight :math:`\kappa`, the base parameter :math:`c_0` and the
        channel's crossover (:func:`residual_weight`).
    keep : slice, optional
        Rows of the solves through the factorisation to keep as :attr:`kept_rows` besides
        their S-part: the Hermitian system makes the residual rows' part of
        :math:`K_0^{-1}P^H` the samples' response to those rows' offsets (for the measurement
        rows, to a change of the measured values: :mod:`updating.inverse.confidence`).
    """

    def __init__(self, factor: InterfaceFactor,
                 channels: Sequence[tuple[Block, Block, float, complex, float]],
                 keep: slice | None = None) -> None:
        n_s = factor.n_s
        index = np.unique(np.concatenate([b.index for load, kinematic, *_ in channels
                                          for b in (load, kinematic)]))
        operators, offsets, self._slices = [], [], []
        start = 0
        for load, kinematic, *_ in channels:
            for block in (load, kinematic):
                rows = np.zeros((len(block.offset), len(index)), dtype=complex)
                rows[:, np.searchsorted(index, block.index)] = block.matrix
                operators.append(rows)
                offsets.append(block.offset)
            n = len(load.offset)
            self._slices.append((slice(start, start + n), slice(start + n, start + 2 * n)))
            start += 2 * n
        self.index, self.operator = index, np.vstack(operators)  # P over its unknowns
        self.weights = [kappa for _, _, kappa, _, _ in channels]
        self.base = [c0 for _, _, _, c0, _ in channels]
        self.crossovers = [crossover for *_, crossover in channels]
        rhs = np.zeros((n_s, start), dtype=complex)
        rhs[index] = self.operator.conj().T
        solution = factor.solve(rhs)
        # copies, not views: the whole solution (every residual row) would stay alive with them
        self.x = solution[factor.n_rho:factor.n_rho + n_s].copy()  # X = K0^{-1} P^H, S-part
        self.kept_rows = (solution[keep] if keep is not None else solution[:0]).copy()
        z = self.operator @ self.x[index]
        self.z = 0.5 * (z + z.conj().T)
        self.y0 = self.operator @ factor.s[index] + np.concatenate(offsets)
        self.s0 = factor.s
        self.e0 = factor.cost
        self._solved = {}

    @classmethod
    def combined(cls, parts: Sequence[JointCondensation]) -> JointCondensation:
        r"""One condensation on the channels of several, all made from the same
        factorisation, without solving again: the cross blocks are
        :math:`Z_{jk} = P_jX_k`."""
        out = cls.__new__(cls)
        out.x = np.hstack([p.x for p in parts])
        out.kept_rows = np.hstack([p.kept_rows for p in parts])
        out.y0 = np.concatenate([p.y0 for p in parts])
        sizes = np.cumsum([0] + [p.operator.shape[0] for p in parts])
        z = np.empty((sizes[-1], sizes[-1]), dtype=complex)
        for a, p in enumerate(parts):
            z[sizes[a]:sizes[a + 1]] = p.operator @ out.x[p.index]
        out.z = 0.5 * (z + z.conj().T)
        out._slices = [tuple(slice(sl.start + offset, sl.stop + offset) for sl in slices)
                       for p, offset in zip(parts, sizes) for slices in p._slices]
        for name in ("weights", "base", "crossovers"):
            setattr(out, name, [v for p in parts for v in getattr(p, name)])
        out.index, out.operator = None, None  # the parts keep theirs
        out.s0, out.e0, out._solved = parts[0].s0, parts[0].e0, {}
        return out

    @staticmethod
    def weight_matrix(kappa: float, c: complex, crossover: float) -> np.ndarray:
        """The 2 x 2 matrix of :math:`M(c)` per sample:
        ``kappa g(c) [[1, -c], [-c*, |c|^2]]`` (:func:`residual_weight`)."""
        factor = kappa * residual_weight(c, crossover)
        return factor * np.array([[1.0, -c], [-np.conj(c), abs(c) ** 2]])

    def _deltas(self, params: Sequence[complex]) -> list[np.ndarray]:
        return [self.weight_matrix(k, c, x) - self.weight_matrix(k, c0, x)
                for k, c, c0, x in zip(self.weights, params, self.base, self.crossovers)]

    def apply(self, coefficients: Sequence[np.ndarray | None], v: np.ndarray) -> np.ndarray:
        r""":math:`\Delta M\,v` (or any matrix of the same structure: per channel 2 x 2
        ``coefficients``, None for zero) on the channels' samples, for ``v`` of shape
        (samples,) or (samples, k)."""
        out = np.zeros_like(v)
        for d, (a, b) in zip(coefficients, self._slices):
            if d is None:
                continue
            out[a] = d[0, 0] * v[a] + d[0, 1] * v[b]
            out[b] = d[1, 0] * v[a] + d[1, 1] * v[b]
        return out

    def _system(self, deltas: Sequence[np.ndarray]) -> np.ndarray:
        r""":math:`I + Z\,\Delta M` for the channels' :math:`\Delta M` coefficients."""
        z_delta = np.empty_like(self.z)  # Z dM by columns: dM's blocks are multiples of I
        for d, (a, b) in zip(deltas, self._slices):
            z_delta[:, a] = self.z[:, a] * d[0, 0] + self.z[:, b] * d[1, 0]
            z_delta[:, b] = self.z[:, a] * d[0, 1] + self.z[:, b] * d[1, 1]
        z_delta[np.diag_indices_from(z_delta)] += 1.0
        return z_delta

    def solve_samples(self, params: Sequence[complex], rhs: np.ndarray) -> np.ndarray:
        r""":math:`(I + Z\,\Delta M)^{-1}` ``rhs`` at ``params``.

        Only the channels whose parameters differ from the base ones have a nonzero
        :math:`\Delta M`; with those samples :math:`a` (the others :math:`b`),
        :math:`y_a = (I + Z_{aa}\Delta M_a)^{-1}r_a` and :math:`y_b = r_b - Z_{ba}\Delta M_ay_a`:
        a solve of the changed channels' size (one joint's, when its neighbours are held).
        """
        deltas = self._deltas(params)
        changed = [i for i, d in enumerate(deltas) if np.any(d)]
        if len(changed) == len(deltas):
            return np.linalg.solve(self._system(deltas), rhs)
        if not changed:
            return np.array(rhs, dtype=complex)
        rows = np.concatenate([np.arange(sl.start, sl.stop) for i in changed
                               for sl in self._slices[i]])
        local = [deltas[i] if i in changed else None for i in range(len(deltas))]
        # dM restricted to the changed samples: its columns there, then those rows
        delta = self.apply(local, np.eye(len(self.z), dtype=complex)[:, rows])[rows]
        small = np.eye(len(rows), dtype=complex) + self.z[np.ix_(rows, rows)] @ delta
        rhs = np.asarray(rhs, dtype=complex)
        y = rhs.copy()
        y[rows] = np.linalg.solve(small, rhs[rows])
        outside = np.setdiff1d(np.arange(len(self.z)), rows)
        y[outside] = rhs[outside] - self.z[np.ix_(outside, rows)] @ (delta @ y[rows])
        return y

    def _solve(self, params: Sequence[complex]) -> tuple[np.ndarray, np.ndarray]:
        # the scans of a correction evaluate the same parameters for the cost and for the
        # neighbourhood's residuals: solve each once
        key = tuple(complex(c) for c in params)
        if key not in self._solved:
            deltas = self._deltas(params)
            y = np.linalg.solve(self._system(deltas), self.y0)
            self._solved[key] = y, self.apply(deltas, y)
        return self._solved[key]

    def cost(self, params: Sequence[complex]) -> float:
        """Cost of the interface problem with the joint's channel parameters ``params``."""
        y, t = self._solve(params)
        return float(self.e0 + np.vdot(t, self.z @ t).real + np.vdot(y, t).real)

    def interface(self, params: Sequence[complex],
                  index: np.ndarray | None = None) -> np.ndarray:
        """Minimiser S at ``params``; with ``index``, only those entries are updated (the others
        keep their values at :math:`c_0`), at a cost proportional to ``len(index)``."""
        _, t = self._solve(params)
        if index is None:
            return self.s0 - self.x @ t
        s = self.s0.copy()
        s[index] -= self.x[index] @ t
        return s
