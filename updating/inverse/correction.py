r""":math:`E_{mod}^2` as a function of one joint's parameters, the others fixed: the cost a
correction optimises (:class:`JointCorrection`).

While one joint is corrected, the problem is condensed once on that joint's residual samples
(:class:`solver.condensation.JointCondensation`), and each cost evaluation is then a dense
solve of their size, whatever the size of the structure. The problem builds and keeps them
(:meth:`updating.inverse.cost.ModifiedProblem.correction`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from typing import Protocol

import numpy as np

from assembly.types import JointParameters
from solver.channels import Channel
from solver.condensation import JointCondensation
from solver.errors import NumericalError
from solver.interface import Block, InterfaceFactor, squared_norm
from solver.joint_rules import channel_parameters
from updating.executor import thread_map
from updating.inverse.problem_data import Evaluation, FrequencyData

__all__ = ["CorrectedProblem", "JointCorrection"]


class CorrectedProblem(Protocol):
    """What a :class:`JointCorrection` reads of the problem it condenses: the part of
    :class:`updating.inverse.cost.ModifiedProblem` it calls (that module builds the
    corrections, so importing it here, even for an annotation, would close an import circle).
    """

    frequencies: dict[float, FrequencyData]
    threads: int

    def joint_weights(self, freq: FrequencyData) -> dict[str, float]: ...

    def neighbourhood(self, joint: str) -> tuple[list[str], list[str]]: ...

    def neighbourhood_cost(self, joint: str, residuals: Mapping[str, float],
                           misfits: Mapping[str, float]) -> float: ...

    def evaluation_at(self, parameters: Mapping[str, Mapping[str, float]],
                      interfaces: dict[float, np.ndarray],
                      data: Mapping[float, Sequence[np.ndarray]] | None = None) -> Evaluation: ...


class JointCorrection:
    """:math:`E_{mod}^2` as a function of one joint's parameters (the others fixed).

    Built once per correction from the factorisations at the current parameters: per
    frequency, a :class:`solver.condensation.JointCondensation` on the joint's residual samples,
    so that each :meth:`cost` is a dense solve of that size, whatever the size of the
    structure.
    """

    def __init__(self, problem: CorrectedProblem, parameters: Mapping[str, Mapping[str, float]],
                 joint: str, factors: Mapping[float, InterfaceFactor]) -> None:
        self.problem = problem
        self.joint = joint
        self.parameters = JointParameters.of(parameters)
        neighbourhood = problem.neighbourhood(joint)

        def condense(frequency: float) -> tuple[float, list[str], JointCondensation]:
            freq = problem.frequencies[frequency]
            system = freq.system
            kappa = problem.joint_weights(freq)[joint]
            params = channel_parameters(parameters, system.omega)
            channels = [ch for ch in system.channels if ch.name == joint]
            factor = factors[frequency]
            # the measurement blocks come last in the factorised problem (evaluate)
            measured = factor.block_rows[-len(freq.operators):]
            condensation = JointCondensation(
                factor, [(ch.load, ch.kinematic, kappa, params[joint, ch.kind], ch.crossover)
                         for ch in channels], keep=slice(measured[0].start, measured[-1].stop))
            return (system.omega, [ch.kind for ch in channels], condensation)

        self._frequencies = dict(zip(problem.frequencies,
                                     thread_map(condense, problem.frequencies, problem.threads)))
        self._neighbourhood = {f: self._local_data(freq, neighbourhood)
                               for f, freq in problem.frequencies.items()}

    def condensation(self, frequency: float) -> JointCondensation:
        """The joint's :class:`solver.condensation.JointCondensation` at ``frequency``; it keeps
        the samples' response to the measured values (``kept_rows``, one row per value)."""
        return self._frequencies[frequency][2]

    @staticmethod
    def _local_data(freq: FrequencyData, neighbourhood: tuple[Sequence[str], Sequence[str]]
                    ) -> tuple[FrequencyData, list[Channel], list[tuple[str, Block, np.ndarray]],
                               np.ndarray, dict[str, float]]:
        """The neighbourhood's channels and measured plates at one frequency, the interface
        unknowns they see, and each measured plate's misfit norm
        (:meth:`~updating.inverse.problem_data.FrequencyData.norms`)."""
        joints, plates = neighbourhood
        channels = [ch for ch in freq.system.channels if ch.name in joints]
        measured = [(pid, op, v) for pid, op, v in zip(freq.plates, freq.operators, freq.data)
                    if pid in plates]
        index = np.unique(np.concatenate([ch.kinematic.index for ch in channels]
                                         + [op.index for _, op, _ in measured]))
        norms = dict(zip(freq.plates, freq.norms()))
        return freq, channels, measured, index, norms

    def _channels(self, values: Mapping[str, float]
                  ) -> Iterator[tuple[float, JointCondensation, list[complex]]]:
        """Per frequency, the joint's channel parameters with ``values`` set."""
        trial = self.parameters.with_joint(self.joint, **values)
        for frequency, (omega, kinds, condensation) in self._frequencies.items():
            params = channel_parameters({self.joint: trial[self.joint]}, omega)
            yield frequency, condensation, [params[self.joint, kind] for kind in kinds]

    def cost(self, **values: float) -> float:
        """:math:`E_{mod}^2` with the joint's ``log10_stiffness`` / ``loss_factor`` / ``mass``
        set to ``values`` (the others as in the base parameters)."""
        total = sum(condensation.cost(params) for _, condensation, params in self._channels(values))
        if not math.isfinite(total):
            raise NumericalError(f"E_mod^2 is not finite at joint {self.joint} {values}")
        return total

    def neighbourhood_cost(self, **values: float) -> float:
        """:meth:`updating.inverse.cost.ModifiedProblem.neighbourhood_cost` of the joint at
        ``values``: only the interface unknowns that its neighbourhood's channels and measured
        plates see are updated, so the cost does not grow with the structure."""
        joints, plates = self.problem.neighbourhood(self.joint)
        residuals, misfits = dict.fromkeys(joints, 0.0), dict.fromkeys(plates, 0.0)
        trial = self.parameters.with_joint(self.joint, **values)
        for frequency, condensation, params in self._channels(values):
            freq, channels, measured, index, norm = self._neighbourhood[frequency]
            s = condensation.interface(params, index)
            all_params = channel_parameters(trial, freq.system.omega)
            e_ref = freq.reference.total
            for ch in channels:
                residuals[ch.name] += ch.energy(s, all_params[ch.name, ch.kind]) / e_ref
            for pid, op, v in measured:
                misfits[pid] += squared_norm(op.residual(s) - v) / norm[pid]
        return self.problem.neighbourhood_cost(self.joint, residuals, misfits)

    def evaluate(self, **values: float) -> Evaluation:
        """Every residual and misfit at the joint's ``values``, from the condensed minimisers
        (no factorisation): what a localisation would find there, without its noise floors."""
        interfaces = {f: condensation.interface(params)
                      for f, condensation, params in self._channels(values)}
        return self.problem.evaluation_at(
            self.parameters.with_joint(self.joint, **values), interfaces)
