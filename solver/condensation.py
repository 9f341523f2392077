r"""The cost of an interface problem as a function of one joint's parameters: its condensation
on the joint's residual samples (``docs/method.md`` section 7.5).

While one joint's parameters :math:`c` vary, only its residual rows change: its residual
samples are
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

from collections.abc import Sequence

import numpy as np

from solver.interface import Block, InterfaceFactor, residual_weight

__all__ = ["JointCondensation"]


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
