"""Localisation–correction strategy over the joints of an assembly (the paper's section 5.2).

Rule (configurable in ``[updating]``):

1. **Localise**: solve the modified problem at the current parameters and rank the joints by
   :math:`E_\\Gamma^2`. The *floor* of each joint is the residual it would show if the model
   were right and only the measurement noise (``[measurement] noise``) and the discretisation
   were at work (:meth:`ModifiedProblem.noise_floor`).
2. **Select** the worst joint among those whose residual stands out of its floor
   (:math:`E_\\Gamma^2 >` ``stop_ratio`` x floor) and that are not *exhausted*. None left:
   stop (status 0).
3. **Correct** only that joint: a bounded optimisation of its log10 k (a scan over
   ``bounds`` then Brent's method around the best point), with its loss factor and line mass
   too when ``identify`` asks for them.
4. If the correction lowered :math:`E_{mod}^2` by less than ``min_decrease`` (relative), the
   joint is exhausted until another joint changes, and the step is undone. Stop after
   ``max_steps`` corrections (status 2).

A joint is reported as *bounded below* when its cost curve stays within 1 % of the minimum up
to the upper bound: a joint much stiffer than the plates around it moves nothing, and only a
lower bound of its stiffness can be identified. Symmetrically, a joint much softer than the
plates acts as a moment-free line and only an upper bound is identifiable.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from updating.cost import log_grid

__all__ = ["Step", "UpdateResult", "TERMINATION_MESSAGES", "correct_joint", "update_joints",
           "localise"]

TERMINATION_MESSAGES = {
    0: "no joint's residual stands out of the noise and discretisation floor",
    1: "no correction lowers E_mod^2 any more",
    2: "the maximum number of correction steps was reached",
}

SCAN_POINTS = 41
FLAT = 0.01  # a cost within 1 % of its minimum cannot be told from it


@dataclass(frozen=True)
class Step:
    """One localisation (step 0) or one correction followed by a localisation."""

    step: int
    selected: str | None
    parameters: dict
    residuals: dict
    floors: dict
    e_mod: float
    e_int: float
    e_mes: float
    interval: tuple | None = None  # log10 k range within 1 % of the optimum (selected joint)

    def to_json(self):
        joints = {}
        for jid, p in self.parameters.items():
            joints[jid] = {
                "log10_stiffness": p["log10_stiffness"], "loss_factor": p["loss_factor"],
                "mass": p["mass"], "residual_percent": 100.0 * self.residuals[jid],
                "floor_percent": 100.0 * self.floors[jid],
            }
        out = {"step": self.step, "selected": self.selected, "e_mod_percent": 100.0 * self.e_mod,
               "e_int_percent": 100.0 * self.e_int, "e_mes_percent": 100.0 * self.e_mes,
               "joints": joints}
        if self.interval is not None:
            out["identified_interval"] = list(self.interval)
        return out


@dataclass(frozen=True)
class UpdateResult:
    """Outcome of :func:`update_joints` (``status`` keys :data:`TERMINATION_MESSAGES`)."""

    steps: tuple
    status: int
    message: str
    parameters: dict = field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.status in (0, 1)

    @property
    def nit(self) -> int:
        return len(self.steps) - 1


def localise(problem, parameters, step=0, selected=None, interval=None, noise=0.0):
    """Evaluate the modified problem and the floors at ``parameters``; returns a :class:`Step`."""
    evaluation = problem.evaluate(parameters)
    # without noise the floor is deterministic (discretisation only): one realisation
    floors = problem.noise_floor(parameters, noise, realisations=4 if noise > 0 else 1)
    return Step(step, selected, {j: dict(p) for j, p in parameters.items()}, evaluation.residuals,
                floors, evaluation.e_mod, evaluation.e_int, evaluation.e_mes, interval)


def correct_joint(problem, parameters, joint, bounds, identify=("stiffness",)):
    """Optimise one joint's parameters, the others fixed; returns ``(parameters, interval)``."""

    def with_value(**values):
        trial = {j: dict(p) for j, p in parameters.items()}
        trial[joint].update(values)
        return trial

    grid = log_grid(bounds, SCAN_POINTS)
    costs = np.array([problem.cost(with_value(log10_stiffness=float(v))) for v in grid])
    best = int(np.argmin(costs))
    lo, hi = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    result = optimize.minimize_scalar(
        lambda v: problem.cost(with_value(log10_stiffness=float(v))),
        bounds=(lo, hi), method="bounded", options={"xatol": 1e-3})
    value = float(result.x) if result.fun <= costs[best] else float(grid[best])
    best_cost = min(float(result.fun), float(costs[best]))
    flat = grid[costs <= best_cost * (1.0 + FLAT) + 1e-15]
    interval = (float(min(flat.min(), value)), float(max(flat.max(), value)))
    updated = with_value(log10_stiffness=value)
    extra = [name for name in ("damping", "mass") if name in identify]
    if extra:
        updated = _optimise_more(problem, updated, joint, bounds, extra)
    return updated, interval


def _optimise_more(problem, parameters, joint, bounds, extra):
    """Joint optimisation of log10 k with the loss factor and/or the log of the line mass."""
    names = ["log10_stiffness"] + [{"damping": "loss_factor", "mass": "mass"}[e] for e in extra]
    start, limits = [], []
    for name in names:
        value = parameters[joint][name]
        if name == "log10_stiffness":
            start.append(value), limits.append(tuple(bounds))
        elif name == "loss_factor":
            start.append(value), limits.append((0.0, 10.0))
        else:
            start.append(np.log10(max(value, 1e-6))), limits.append((-6.0, 1.0))

    def unpack(x):
        trial = {j: dict(p) for j, p in parameters.items()}
        for name, v in zip(names, x):
            trial[joint][name] = float(10.0**v) if name == "mass" else float(v)
        return trial

    result = optimize.minimize(lambda x: problem.cost(unpack(x)), np.array(start),
                               method="L-BFGS-B", bounds=limits)
    return unpack(result.x)


def update_joints(problem, settings, noise=0.0, start=None, on_step=None):
    """The localisation–correction loop.

    Parameters
    ----------
    problem : updating.cost.ModifiedProblem
    settings : assembly.models.Updating
        ``bounds``, ``identify``, ``max_steps``, ``stop_ratio``, ``min_decrease``.
    noise : float
        Measurement noise level used for the floors.
    start : sequence of Step, optional
        Steps of an earlier run to continue from (resume).
    on_step : callable, optional
        Called with each finished :class:`Step` (to save progress).

    Returns
    -------
    UpdateResult
    """
    steps = list(start or [])
    if not steps:
        steps.append(localise(problem, problem.initial_parameters(), noise=noise))
        if on_step:
            on_step(steps[-1])
    exhausted = set()
    status = 2
    while len(steps) - 1 < settings.max_steps:
        current = steps[-1]
        candidates = [j for j in sorted(current.residuals, key=current.residuals.get, reverse=True)
                      if current.residuals[j] > settings.stop_ratio * current.floors[j]
                      and j not in exhausted]
        if not candidates:
            status = 0 if not exhausted else 1
            break
        joint = candidates[0]
        parameters, interval = correct_joint(problem, current.parameters, joint,
                                             settings.bounds, settings.identify)
        step = localise(problem, parameters, len(steps), joint, interval, noise)
        if current.e_mod - step.e_mod < settings.min_decrease * current.e_mod:
            exhausted.add(joint)
            continue
        exhausted.clear()
        steps.append(step)
        if on_step:
            on_step(step)
    return UpdateResult(tuple(steps), status, TERMINATION_MESSAGES[status], steps[-1].parameters)
