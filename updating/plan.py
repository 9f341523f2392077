r"""Identifiability before the test (``vtcr plan``): what the planned measurement can tell.

For the model as described (its joints at their values) and the planned points (the
description's grid, or a measurement file's points), per joint:

* **Field sensitivity** per frequency: the relative change of the model's values at the
  planned points, :math:`\|p(\theta + 0.1) - p(\theta)\| / \|p(\theta)\|`, for +0.1 decade of
  log10 k, and for +0.1 of the joint's loss factor. Computed through the joint's condensation
  of the model response (:class:`solver.interface.JointCondensation`), no new factorisation.
* **Expected interval**: the confidence interval (:mod:`updating.confidence`) that the stated
  noise (:data:`ASSUMED_NOISE` when none is stated) gives when the measured values are the
  model's own prediction: the typical interval of a test of a right model. Two-sided:
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
from dataclasses import dataclass, field

import numpy as np

from solver.interface import JointCondensation
from updating.confidence import ConfidenceInterval, NoiseModel, confidence_interval, noise_model
from updating.cost import ModifiedProblem, channel_parameters
from updating.measurements import Measurements

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
    def best_source(self):
        """The (frequency, plate) that carries most of the joint's information."""
        return max(self.information, key=self.information.get) if self.information else None

    def to_json(self):
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


def _model_measurements(case, layout_measurements):
    """The planned points with the model's own values (placeholders first: the problem is
    built on the points, then given the model's prediction there)."""
    return Measurements({f: {pid: (points, np.ones(len(points), dtype=complex))
                             for pid, (points, _) in plates.items()}
                         for f, plates in layout_measurements.data.items()})


def identifiability_plan(case, layout_measurements, level=None, resolution=None, threads=1):
    """``({joint: JointPlan}, noise)`` of ``case`` measured at the points of
    ``layout_measurements`` (their values are not used)."""
    level = case.updating.confidence if level is None else level
    problem = ModifiedProblem(case, _model_measurements(case, layout_measurements),
                              resolution=resolution, threads=threads)
    parameters = problem.initial_parameters()
    prediction = problem.synthetic_data(parameters, 0.0, realisations=1)[0]
    problem = problem.with_data(prediction)
    stated = case.measurement.noise
    noise = (noise_model(stated, 0.0) if stated > 0.0 else
             NoiseModel("uniform", ASSUMED_NOISE, "assumed: [measurement] noise states none"))
    direct = problem.direct_factors(parameters)
    plans = {}
    for joint in case.joints:
        stiffness, damping, information, share = {}, {}, {}, {}
        for frequency, freq in problem.frequencies.items():
            system = freq.system
            own = [ch for ch in system.channels if ch.joint == joint]
            params = channel_parameters(parameters, system.omega)
            condensation = JointCondensation(
                direct[frequency], [(ch.load, ch.kinematic, problem.alpha[joint],
                                     params[joint, ch.kind], ch.crossover) for ch in own])

            def values(**change):
                trial = {joint: dict(parameters[joint], **change)}
                c = channel_parameters(trial, system.omega)
                s = condensation.interface([c[joint, ch.kind] for ch in own])
                return [op.residual(s) for op in freq.operators]

            base = values()
            theta = parameters[joint]["log10_stiffness"]
            moved = values(log10_stiffness=theta + SENSITIVITY_STEP)
            damped = values(loss_factor=parameters[joint]["loss_factor"] + DAMPING_STEP)
            norm = math.sqrt(sum(float(np.vdot(b, b).real) for b in base))
            stiffness[frequency] = _relative_change(moved, base, norm)
            damping[frequency] = _relative_change(damped, base, norm)
            for pid, b, m in zip(freq.plates, base, moved):
                sigma2 = (noise.level**2 / 3.0 if noise.kind == "uniform" else noise.level**2)
                derivative = (m - b) / SENSITIVITY_STEP
                information[frequency, pid] = float(
                    np.sum(np.abs(derivative) ** 2 / np.maximum(sigma2 * np.abs(b) ** 2,
                                                                np.finfo(float).tiny)))
            share[frequency] = _dissipated_share(system, condensation, own, params, joint)
        total = sum(information.values()) or 1.0
        n_values = sum(len(v) for f in problem.frequencies.values() for v in f.data)
        threshold = 2.0 * (noise.level / math.sqrt(3.0)) / math.sqrt(max(n_values, 1))
        target = (joint, "log10_stiffness")
        interval = confidence_interval(problem, parameters, target, [target], noise, level,
                                       case.updating.bounds)
        plans[joint] = JointPlan(joint, parameters[joint]["log10_stiffness"], stiffness, damping,
                                 interval, share, max(damping.values()) > threshold,
                                 {key: v / total for key, v in information.items()})
    return plans, noise


def _relative_change(moved, base, norm):
    return math.sqrt(sum(float(np.vdot(m - b, m - b).real) for m, b in zip(moved, base))) / norm


def _dissipated_share(system, condensation, own, params, joint):
    r"""Power the joint dissipates, :math:`\tfrac12\omega\,\mathrm{Im}\,c\int|[q]|^2`, over the
    power the loads inject (the plates' and the joints' dissipation together, the model's
    power balance)."""
    from solver.power import plate_powers

    s = condensation.interface([params[joint, ch.kind] for ch in own])
    omega = system.omega
    joint_power = sum(0.5 * omega * params[joint, ch.kind].imag
                      * float(np.vdot(ch.kinematic.residual(s), ch.kinematic.residual(s)).real)
                      for ch in own)
    amplitudes = system.plate_amplitudes(s)
    injected = sum(plate_powers(system.problems[pid], system.bases[pid], amplitudes[pid])[0]
                   for pid in system.problems)
    return joint_power / injected if injected > 0 else math.nan
