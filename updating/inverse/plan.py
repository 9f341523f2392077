r"""Identifiability before the test (``vtcr plan``): what the planned measurement can tell.

For the model as described (its joints at their values) and the planned points (the
description's grid, or a measurement file's points), per joint:

* **Field sensitivity** per frequency: the relative change of the model's values at the
  planned points, :math:`\|p(\theta + 0.1) - p(\theta)\| / \|p(\theta)\|`, for +0.1 decade of
  log10 k, and for +0.1 of the joint's loss factor. Computed through the joint's condensation
  of the model response (:class:`solver.condensation.JointCondensation`), no new
  factorisation.
* **Expected interval**: the confidence interval (:mod:`updating.inverse.confidence`) that the stated
  noise (:data:`ASSUMED_NOISE` when none is stated) gives when the measured values are the
  model's own prediction plus typical noise (the statistic of the noise-free prediction moved
  by the noise's mean effect on it: ``confidence_interval(expected=True)``): the typical
  interval of a test of a right model. Two-sided:
  *identifiable*; one bound only: *bounded* (a near-rigid or near-hinge joint); neither:
  *invisible* at these points and frequencies.
* **Damping**: the share of the injected power the joint dissipates, and whether the field
  change for +0.1 of its loss factor rises above the noise: above two standard errors of the
  noise averaged over the planned values, :math:`2\,(\varepsilon/\sqrt3)/\sqrt N` (uniform
  noise of half-width :math:`\varepsilon`, N values); below it the loss factor cannot be told
  from the noise (the paper's folded plate, whose joint dissipates little).
* **Where information comes from**: per (frequency, plate), the share of the joint's Fisher
  information :math:`\sum_n|\partial p_n/\partial\theta|^2/\sigma_n^2` (:math:`\sigma_n` the
  noise of value n); the best pair is the suggestion for a joint that is not identifiable.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from solver.power import carries_loads, injected_power
from updating.inverse.confidence import (
    ConfidenceInterval,
    NoiseModel,
    ScoreTest,
    confidence_interval,
    noise_model,
)
from updating.inverse.cost import ModifiedProblem, channel_parameters

if TYPE_CHECKING:
    from assembly import Case
    from solver.estimate import ErrorEstimate
    from solver.substructure import AssemblySystem, Channel
    from updating.data.measurements import Measurements
    from updating.executor import Executor

__all__ = ["JointPlan", "identifiability_plan", "SENSITIVITY_STEP", "DAMPING_STEP"]

SENSITIVITY_STEP = 0.1  # decade of log10 k
DAMPING_STEP = 0.1  # loss factor
ASSUMED_NOISE = 0.01
"""Noise of a planned test whose description states none (a plan without noise would promise
intervals of the discretisation's width)."""


@dataclass(frozen=True)
class JointPlan:
    """What the planned measurement tells about one joint."""

    joint: str
    value: float  # log10 k of the model
    stiffness_sensitivity: dict  # frequency -> relative change (fraction) per +0.1 decade
    damping_sensitivity: dict  # frequency -> relative change (fraction) per +0.1 loss factor
    interval: ConfidenceInterval
    damping_share: dict  # frequency -> joint's dissipated power / injected power
    damping_identifiable: bool
    information: dict = field(default_factory=dict)  # (frequency, plate) -> share of the total

    @property
    def verdict(self) -> str:
        return {"two-sided": "identifiable", "lower": "bounded", "upper": "bounded"}.get(
            self.interval.kind, "invisible")

    @property
    def best_source(self) -> tuple[float, str] | None:
        """The (frequency, plate) that carries most of the joint's information."""
        return max(self.information, key=self.information.get) if self.information else None

    def to_json(self) -> dict[str, Any]:
        return {
            "log10_stiffness": self.value, "verdict": self.verdict,
            "sensitivity_percent_per_0.1_decade": {
                f"{f:g}": 100 * v for f, v in self.stiffness_sensitivity.items()},
            "sensitivity_percent_per_0.1_loss_factor": {
                f"{f:g}": 100 * v for f, v in self.damping_sensitivity.items()},
            "expected": self.interval.to_json(),
            "damping": {"dissipated_share": {f"{f:g}": v for f, v in self.damping_share.items()},
                        "identifiable": self.damping_identifiable},
            "information": [{"frequency": f, "plate": p, "share": s}
                            for (f, p), s in sorted(self.information.items(),
                                                    key=lambda item: -item[1])]}


def identifiability_plan(case: Case, layout_measurements: Measurements,
                         level: float | None = None,
                         resolution: float | Mapping[str, float] | None = None, threads: int = 1,
                         estimate: bool = False, joints: Iterable[str] | None = None,
                         on_joint: Callable[[str], object] | None = None,
                         executor: Executor | None = None
                         ) -> tuple[dict[str, JointPlan], NoiseModel, dict[float, ErrorEstimate]]:
    """``({joint: JointPlan}, noise, {frequency: ErrorEstimate})`` of ``case`` measured at the
    points of ``layout_measurements`` (their values are not used: the problem is given the
    model's own prediction there); the estimates of the model's discretisation error, which
    the sensitivities are read against, with ``estimate`` (else empty).

    ``joints`` restricts the plan to those updatable joints (default: every one): each joint costs
    two condensations (solves through the factorisations, together about 40 % of a factorisation in
    a large structure; :meth:`solver.sizing.SizeEstimate.plan_seconds`), so a large structure is
    planned region by region. ``on_joint(joint)`` is called after each joint (progress);
    ``executor`` (:class:`updating.executor.Executor`) builds the frequencies in parallel."""
    level = case.updating.confidence if level is None else level
    problem = ModifiedProblem(case, layout_measurements, resolution=resolution,
                              threads=threads, estimate=estimate, executor=executor)
    estimates = problem.error_estimates
    parameters = problem.initial_parameters()
    prediction = problem.synthetic_data(parameters, 0.0, realisations=1)[0]
    problem = problem.with_data(prediction)
    stated = case.measurement.noise
    noise = (noise_model(stated, 0.0) if stated > 0.0 else
             NoiseModel("uniform", ASSUMED_NOISE, "assumed: [measurement] noise states none"))
    variance = noise.deviation**2  # relative, of one value
    n_values = sum(len(v) for f in problem.frequencies.values() for v in f.data)
    threshold = 2.0 * noise.deviation / math.sqrt(max(n_values, 1))
    direct = problem.direct_factors(parameters)
    # the power the loads inject, every joint's damping share's denominator: the model's
    # response, the same for every joint
    injected = {frequency: _injected_power(freq.system, direct[frequency].s)
                for frequency, freq in problem.frequencies.items()}
    plans = {}
    planned = problem.joints if joints is None else set(joints)
    for joint in (j for j in problem.joints if j in planned):
        target = (joint, "log10_stiffness")
        # the test's condensation of the model response on the joint gives the sensitivities
        test = ScoreTest(problem, parameters, target, [target], direct=direct)
        theta = parameters[joint]["log10_stiffness"]
        changes = {"base": {}, "moved": {target: theta + SENSITIVITY_STEP},
                   "damped": {(joint, "loss_factor"):
                              parameters[joint]["loss_factor"] + DAMPING_STEP}}
        stiffness, damping, information, share = {}, {}, {}, {}
        for (frequency, freq), at in zip(problem.frequencies.items(), test.frequencies):
            responses = {name: at.response(change) for name, change in changes.items()}
            base, moved, damped = ([op.residual(responses[name]) for op in freq.operators]
                                   for name in ("base", "moved", "damped"))
            norm = math.sqrt(sum(float(np.vdot(b, b).real) for b in base))
            stiffness[frequency] = _relative_change(moved, base, norm)
            damping[frequency] = _relative_change(damped, base, norm)
            for pid, b, m in zip(freq.plates, base, moved):
                derivative = (m - b) / SENSITIVITY_STEP
                information[frequency, pid] = float(
                    np.sum(np.abs(derivative) ** 2 / np.maximum(variance * np.abs(b) ** 2,
                                                                np.finfo(float).tiny)))
            share[frequency] = _dissipated_share(freq.system, responses["base"], at.own,
                                                 channel_parameters(parameters,
                                                                    freq.system.omega), joint,
                                                 injected[frequency])
        total = sum(information.values()) or 1.0
        interval = confidence_interval(problem, parameters, target, [target], noise, level,
                                       case.updating.bounds, test=test, expected=True)
        plans[joint] = JointPlan(joint, theta, stiffness, damping, interval, share,
                                 max(damping.values()) > threshold,
                                 {key: v / total for key, v in information.items()})
        if on_joint:
            on_joint(joint)
    return plans, noise, estimates


def _relative_change(moved: Sequence[np.ndarray], base: Sequence[np.ndarray],
                     norm: float) -> float:
    return math.sqrt(sum(float(np.vdot(m - b, m - b).real) for m, b in zip(moved, base))) / norm


def _injected_power(system: AssemblySystem, s: np.ndarray) -> float:
    """The power the loads inject at interface unknowns ``s`` (:func:`solver.power.
    injected_power` summed over the plates that carry loads)."""
    loaded = [pid for pid, problem in system.problems.items() if carries_loads(problem)]
    amplitudes = system.plate_amplitudes(s, loaded)
    return sum(injected_power(system.problems[pid], system.bases[pid], amplitudes[pid])
               for pid in loaded)


def _dissipated_share(system: AssemblySystem, s: np.ndarray, own: Iterable[Channel],
                      params: Mapping[tuple[str, str], complex], joint: str,
                      injected: float) -> float:
    r"""Power the joint dissipates at interface unknowns ``s``,
    :math:`\tfrac12\omega\,\mathrm{Im}\,c\,\|\Pi_\psi[q]\|^2`
    (:meth:`solver.channels.Channel.dissipated_power`), over the power ``injected`` by the
    loads (the plates' and the joints' dissipation together, the model's power balance)."""
    joint_power = sum(ch.dissipated_power(s, params[joint, ch.kind], system.omega)
                      for ch in own)
    return joint_power / injected if injected > 0 else math.nan
