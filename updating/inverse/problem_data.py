r"""The records of the modified problem: what it holds for one measured frequency
(:class:`FrequencyData`, built once) and what one evaluation of :math:`E_{mod}^2` gives
(:class:`Evaluation`).

They live apart from :class:`updating.inverse.cost.ModifiedProblem`, which builds and returns
them, so that :class:`updating.inverse.correction.JointCorrection`, which the problem builds,
reads them too without an import circle.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from solver.estimate import ErrorEstimate
from solver.interface import Block, squared_norm
from solver.substructure import AssemblySystem, ReferenceEnergy

__all__ = ["Evaluation", "FrequencyData"]


@dataclass(frozen=True)
class Evaluation:
    """E_mod^2 and its parts at one parameter set (dimensionless; sums over frequencies)."""

    e_mod: float
    e_int: float
    e_mes: float
    residuals: dict[str, float]  # joint -> E_Gamma^2
    interface: dict[float, np.ndarray]  # frequency -> S
    misfits: dict[str, float]  # measured plate -> its part of E_mes^2


def _norm2(values: Iterable[np.ndarray]) -> float:
    return sum(squared_norm(v) for v in values)


def _norms(values: Sequence[np.ndarray], per_plate: bool) -> np.ndarray:
    r"""Per measured plate, what its squared misfit is divided by: every plate the whole
    data's :math:`\|\tilde u\|^2` (``[updating] misfit = "global"``), or its own
    :math:`\|\tilde u_p\|^2 M/m_p` (``"per_plate"``: :math:`m_p` of the :math:`M` measured
    values on plate p), so that :math:`E_{mes}^2` is the mean over the measured values of
    their plate's relative misfit: under relative noise :math:`\pm\varepsilon` it is about
    :math:`\varepsilon^2/3` whatever the number of plates (``docs/updating.md``, section 2)."""
    if per_plate:
        total = sum(np.size(v) for v in values)
        return np.array([float(np.vdot(v, v).real) * total / max(np.size(v), 1)
                         for v in values])
    return np.full(len(values), _norm2(values))


@dataclass
class FrequencyData:
    """One measured frequency of a :class:`~updating.inverse.cost.ModifiedProblem`
    (``problem.frequencies[f]``): its assembly system and, per measured plate, the measured
    ``w`` as a Block over the plate's interface unknowns with the measured values, the
    normalisation of its misfit and the model's discretisation error there."""

    system: AssemblySystem
    reference: ReferenceEnergy  # E_ref of the model's response at p0
    plates: list[str]  # measured plates
    operators: list[Block]  # per measured plate: w at its points per unit S, and at S = 0
    data: list[np.ndarray]  # measured values per measured plate
    initial_s: np.ndarray  # the model response's S at p0 (the E_ref solve)
    estimate: ErrorEstimate | None = None  # of that response, if asked for
    per_plate: bool = False  # each plate's misfit relative to its own data ([updating] misfit)
    discretisation: list[np.ndarray] | None = None  # w+ - w_h at each plate's points (p0)
    no_discretisation: str = ""  # why ``discretisation`` is None (the enriched solve's cost)

    def norms(self, data: Sequence[np.ndarray] | None = None) -> np.ndarray:
        """Per measured plate, what its squared misfit is divided by (:func:`_norms`), for
        measured values ``data`` (default the measured ones)."""
        return _norms(self.data if data is None else data, self.per_plate)

    def scale(self, r: float, data: Sequence[np.ndarray] | None = None,
              norm: np.ndarray | None = None) -> np.ndarray:
        r"""Per measured plate, :math:`\sqrt{r/N_p}`: the weight of its measurement rows for
        measured values ``data`` (default the measured ones), :math:`N_p` the plates'
        ``norm`` (default :meth:`norms` of the data)."""
        return np.sqrt(r / (self.norms(data) if norm is None else norm))

    def value_scale(self, r: float) -> np.ndarray:
        """:meth:`scale` of the measured data, one entry per measured value."""
        return np.repeat(self.scale(r), [len(v) for v in self.data])

    def blocks(self, data: Sequence[np.ndarray], r: float,
               norm: np.ndarray | None = None) -> list[Block]:
        r"""The measurement term :math:`r E_{mes}^2` as Blocks, for measured values ``data``
        normalised by ``norm`` (per plate; default :meth:`norms` of the data)."""
        scales = self.scale(r, data, norm)
        return [Block(op.index, scale * op.matrix, scale * (op.offset - v))
                for op, v, scale in zip(self.operators, data, scales)]

    def misfits(self, s: np.ndarray, data: Sequence[np.ndarray],
                norm: np.ndarray | None = None) -> dict[str, float | np.ndarray]:
        """Per measured plate, its part of :math:`E_{mes}^2` at interface unknowns ``s`` for
        measured values ``data`` (normalised by ``norm``, default :meth:`norms` of the
        data). With ``s`` of shape (n_s, k) and each plate's values of shape (points, k), one
        part per column (``norm`` given: the columns share it)."""
        norm = self.norms(data) if norm is None else norm
        return {pid: squared_norm(op.residual(s) - v) / n
                for pid, op, v, n in zip(self.plates, self.operators, data, norm)}
