"""Localisation–correction strategy over the joints of an assembly (the paper's section 5.2).

Rule (configurable in ``[updating]``):

1. **Localise**: solve the modified problem at the current parameters and rank the joints by
   :math:`E_\\Gamma^2`. The *floor* of each joint is the residual it would show on average if
   the model were right and only the measurement noise (``[measurement] noise``) and the
   discretisation were at work, its *threshold* the residual such a right model exceeds at any
   of the joints with probability ``significance`` (familywise), both from
   :data:`~updating.inverse.significance.FLOOR_DRAWS` synthetic experiments on the model
   (:meth:`ModifiedProblem.floor_draws`, :mod:`updating.inverse.significance`), and never below
   ``stop_ratio`` x floor. Among 180 joints a ratio to the floor is exceeded several times
   by noise alone; the threshold counts the joints.
2. **Select** among the joints whose residual stands out (:math:`E_\\Gamma^2 >` threshold) and
   that are not *exhausted* the one that stands out most (largest residual-to-threshold
   ratio: in a large structure the floors differ by an order of magnitude between the loaded
   region and the rest, and the largest residual is often a noisy joint near the load, not
   the most significant one).
3. **Correct** only that joint: a bounded optimisation of its log10 k (a scan over
   ``bounds`` then Brent's method around the best point), with its loss factor and line mass
   too when ``identify`` asks for them. The cost is condensed once on the joint
   (:meth:`ModifiedProblem.correction`): an evaluation does not grow with the structure.
   Other standing joints whose neighbourhoods share no joint with it (nor with each other)
   are corrected in the same step, each on its own with the others at their current values
   (:func:`_apart`): in a large structure wrong joints far apart do not see each other, and
   one localisation then serves them all. On a 2 x 2 layout every neighbourhood overlaps, so
   the paper's one-joint steps are unchanged.
4. **Judge it locally.** If the correction lowered the cost of the joint's *neighbourhood*
   (its two plates' measurement misfit and the residuals of every joint on those plates,
   :meth:`ModifiedProblem.neighbourhood_cost`) by less than ``min_decrease`` of that cost,
   or if it raised the joint's own residual (it then bought a lower misfit of a few plates
   with a worse joint law: it fits the measurement noise), the joint is exhausted until
   another joint changes, and that correction is undone (the others of the step stand on
   their own decisions). A fraction of
   the global :math:`E_{mod}^2` would be diluted by the size of the structure: in a 20-plate
   chain one wrong joint is a few per cent of it. The neighbourhood's cost is bounded below by
   its noise floor, so near the floor the threshold is a fraction of the noise level.
5. **Re-correct** when no joint stands out any more: a joint corrected while other joints were
   still wrong has compensated for them, and its residual can sit near the floor while its
   value is biased (the paper's Table 4 re-corrects Γ1 and Γ2 for this reason). The joints
   corrected so far are tried again, largest residual-to-threshold ratio first, under the same
   ``min_decrease`` rule; an accepted re-correction starts a new localisation.

The loop stops when no joint stands out and no re-correction lowers its neighbourhood's cost
(status 0), when joints stand out but no correction lowers its neighbourhood's cost
(status 1), or after ``max_steps`` accepted corrections (status 2).

Each corrected joint is reported with a calibrated confidence interval at ``[updating]
confidence`` (:mod:`updating.inverse.confidence`): a two-sided range, or one bound only where the
data bound the value on one side (a joint much stiffer than the plates around it moves nothing,
so only ``>= x`` is identifiable; a joint much softer acts as a moment-free line: ``<= x``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy import optimize

from assembly.types import JointParameters
from updating.inverse.confidence import confidence_intervals
from updating.inverse.correction import JointCorrection
from updating.inverse.cost import (
    PARAMETER_BOUNDS,
    SMALLEST_MASS,
    ModifiedProblem,
    log_grid,
    with_joint,
)
from updating.inverse.problem_data import Evaluation
from updating.inverse.significance import FLOOR_DRAWS, standing_thresholds

if TYPE_CHECKING:
    from assembly.settings import Updating

__all__ = ["Step", "UpdateResult", "TERMINATION_MESSAGES", "correct_joint", "update_joints",
           "localise", "thresholds", "flat_interval", "finished_result", "standing_summary",
           "excess_ratios"]

TERMINATION_MESSAGES = {
    0: "no joint's residual stands out of the noise and discretisation floor, and re-correcting "
       "the corrected joints no longer lowers the cost around them",
    1: "no correction lowers the cost around its joint any more",
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
    recorrection: bool = False  # selected to be corrected again, not for standing out
    e_mod_floor: float = 0.0  # E_mod^2 a correct model shows under the stated noise
    misfits: dict = field(default_factory=dict)  # measured plate -> its part of E_mes^2
    also: dict = field(default_factory=dict)  # joint -> interval: corrected in the same step
    # joint -> residual above which it stands out (empty in run files written before the
    # thresholds were calibrated: stop_ratio x floor then)
    thresholds: dict = field(default_factory=dict)

    @property
    def corrected(self) -> tuple[str, ...]:
        """Every joint corrected in this step: ``selected``, then those of ``also``."""
        return ((self.selected,) if self.selected is not None else ()) + tuple(self.also)

    def to_record(self) -> dict[str, Any]:
        """Every field at full precision (JSON floats round-trip exactly), for run files."""
        record = dataclasses.asdict(self)
        record["interval"] = list(self.interval) if self.interval is not None else None
        record["also"] = {j: list(v) for j, v in self.also.items()}
        return record

    @classmethod
    def from_record(cls, record: Mapping[str, Any]) -> Step:
        """Inverse of :meth:`to_record`."""
        record = dict(record)
        if record.get("interval") is not None:
            record["interval"] = tuple(record["interval"])
        record["also"] = {j: tuple(v) for j, v in record.get("also", {}).items()}
        return cls(**record)

    def to_json(self) -> dict[str, Any]:
        joints = {}
        for jid, p in self.parameters.items():
            joints[jid] = {
                "log10_stiffness": p["log10_stiffness"], "loss_factor": p["loss_factor"],
                "mass": p["mass"], "residual_percent": 100.0 * self.residuals[jid],
                "floor_percent": 100.0 * self.floors[jid],
            }
            if jid in self.thresholds:
                joints[jid]["threshold_percent"] = 100.0 * self.thresholds[jid]
        out = {"step": self.step, "selected": self.selected, "e_mod_percent": 100.0 * self.e_mod,
               "e_int_percent": 100.0 * self.e_int, "e_mes_percent": 100.0 * self.e_mes,
               "e_mod_floor_percent": 100.0 * self.e_mod_floor, "joints": joints}
        if self.interval is not None:
            out["identified_interval"] = list(self.interval)
        if self.also:
            out["also_selected"] = {j: {"identified_interval": list(v)}
                                    for j, v in self.also.items()}
        if self.recorrection:
            out["recorrection"] = True
        return out


@dataclass(frozen=True)
class UpdateResult:
    """Outcome of :func:`update_joints` (``status`` keys :data:`TERMINATION_MESSAGES`)."""

    steps: tuple
    status: int
    message: str
    parameters: dict = field(default_factory=dict)
    intervals: dict = field(default_factory=dict)  # corrected joint -> its log10 k interval
    parameter_intervals: dict = field(default_factory=dict)  # (joint, name) -> the others

    @property
    def success(self) -> bool:
        return self.status in (0, 1)

    @property
    def nit(self) -> int:
        return len(self.steps) - 1


def localise(problem: ModifiedProblem, parameters: Mapping[str, Mapping[str, float]],
             step: int = 0, selected: str | None = None,
             interval: tuple[float, float] | None = None, noise: float = 0.0,
             recorrection: bool = False, also: Mapping[str, tuple[float, float]] | None = None,
             settings: Updating | None = None) -> Step:
    """Evaluate the modified problem at ``parameters``, with each joint's floor and its
    threshold from :data:`FLOOR_DRAWS` synthetic experiments on the model; returns a
    :class:`Step`.

    The threshold is the residual a right model exceeds at any joint with probability
    ``settings.significance`` (:mod:`updating.inverse.significance`), and never below
    ``settings.stop_ratio`` times the floor (default ``settings``: the description's)."""
    settings = problem.case.updating if settings is None else settings
    evaluation = problem.evaluate(parameters)
    # without noise the floor is deterministic (discretisation only): one realisation
    draws, e_mod_draws = problem.floor_draws(parameters, noise,
                                             realisations=FLOOR_DRAWS if noise > 0 else 1)
    floors = dict(zip(problem.joints, draws.mean(axis=1)))
    calibrated = standing_thresholds(draws, settings.significance)
    thresholds = {j: max(settings.stop_ratio * floors[j], float(t))
                  for j, t in zip(problem.joints, calibrated)}
    return Step(step, selected, JointParameters.of(parameters), evaluation.residuals,
                floors, evaluation.e_mod, evaluation.e_int, evaluation.e_mes, interval,
                recorrection, float(e_mod_draws.mean()), evaluation.misfits, dict(also or {}),
                thresholds)


def flat_interval(grid: np.ndarray, costs: np.ndarray, best: int, value: float,
                  best_cost: float) -> tuple[float, float]:
    """The scanned values around the optimum whose cost is within :data:`FLAT` of the minimum.

    Only the run of grid points contiguous with the best one counts (another valley elsewhere
    is not an uncertainty of this optimum); the interval always contains ``value``.
    """
    threshold = best_cost * (1.0 + FLAT)
    lo = hi = best
    while lo > 0 and costs[lo - 1] <= threshold:
        lo -= 1
    while hi < len(grid) - 1 and costs[hi + 1] <= threshold:
        hi += 1
    low, high = (grid[lo], grid[hi]) if costs[best] <= threshold else (value, value)
    return float(min(low, value)), float(max(high, value))


def _minimise_on_log_scale(cost: Callable[[float], float], bounds: tuple[float, float],
                           n_scan: int) -> tuple[float, float, np.ndarray, np.ndarray, int]:
    """Scan ``cost(log10 k)`` on ``n_scan`` points over ``bounds``, then Brent around the best.

    Returns ``(value, minimum, grid, costs, best index)``; the scan keeps Brent out of the
    other valleys a cost curve in log10 k can have.
    """
    grid = log_grid(bounds, n_scan)
    costs = np.array([cost(float(v)) for v in grid])
    best = int(np.argmin(costs))
    lo, hi = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    result = optimize.minimize_scalar(cost, bounds=(lo, hi), method="bounded",
                                      options={"xatol": 1e-3})
    if result.fun <= costs[best]:
        return float(result.x), float(result.fun), grid, costs, best
    return float(grid[best]), float(costs[best]), grid, costs, best


def correct_joint(problem: ModifiedProblem, parameters: Mapping[str, Mapping[str, float]],
                  joint: str, bounds: tuple[float, float], identify: Sequence[str] = ("stiffness",)
                  ) -> tuple[dict[str, dict[str, float]], tuple[float, float], Evaluation]:
    """Optimise one joint's parameters, the others fixed.

    Returns ``(parameters, interval, evaluation)``: the evaluation (residuals and misfits) at
    the optimum comes from the condensed minimiser, without a new factorisation.

    The cost is condensed once on the joint (:meth:`ModifiedProblem.correction`), so each
    evaluation is a small dense solve whatever the size of the structure. ``interval`` is the
    log10 k range that cannot be told from the optimum: the scanned values whose neighbourhood
    cost is within :data:`FLAT` of its minimum (:func:`_neighbourhood_interval`).
    """
    local = problem.correction(parameters, joint)
    value, _, grid, _, _ = _minimise_on_log_scale(
        lambda v: local.cost(log10_stiffness=v), bounds, SCAN_POINTS)
    low, high = _neighbourhood_interval(local, grid, value)
    updated = with_joint(parameters, joint, log10_stiffness=value)
    extra = [name for name in ("damping", "mass") if name in identify
             and (name != "mass" or problem.has_line_mass(joint))]
    if extra:
        updated = _optimise_more(local, updated, joint, bounds, extra)
    return updated, (low, high), local.evaluate(**updated[joint])


# optimisation variable of each joint parameter: (name, to variable, from variable, bounds);
# the line mass is optimised on a log scale, as the stiffness (its bounds are the updating
# bounds, given per call)
_EXTRA_VARIABLES = {
    "damping": ("loss_factor", float, float, PARAMETER_BOUNDS["loss_factor"]),
    "mass": ("mass", lambda m: np.log10(max(m, SMALLEST_MASS)), lambda x: float(10.0**x),
             tuple(np.log10(PARAMETER_BOUNDS["mass"]))),
}


def _optimise_more(local: JointCorrection, parameters: Mapping[str, Mapping[str, float]],
                   joint: str, bounds: tuple[float, float],
                   extra: Sequence[str]) -> dict[str, dict[str, float]]:
    """Joint optimisation of log10 k with the loss factor and/or the log of the line mass
    (``local``: the joint's :class:`updating.inverse.correction.JointCorrection`)."""
    variables = [("log10_stiffness", float, float, tuple(bounds))]
    variables += [_EXTRA_VARIABLES[e] for e in extra]
    start = np.array([to_x(parameters[joint][name]) for name, to_x, _, _ in variables])

    def values(x: np.ndarray) -> dict[str, float]:
        return {name: from_x(v) for (name, _, from_x, _), v in zip(variables, x)}

    # L-BFGS-B's tolerances are absolute below a cost of 1 (its relative decrease is taken
    # over max(|f|, 1)), and E_mod^2 is often 1e-6: at its own scale the cost stopped at the
    # start whatever the loss factor's data said. The cost is optimised relative to its value
    # at the start, whose steps and gradients are then of order one.
    scale = local.cost(**values(start))
    scale = scale if scale > 0.0 else 1.0
    result = optimize.minimize(lambda x: local.cost(**values(x)) / scale, start,
                               method="L-BFGS-B", bounds=[limits for *_, limits in variables],
                               options={"ftol": 1e-12, "gtol": 1e-9})
    return with_joint(parameters, joint, **values(result.x))


def thresholds(step: Step, stop_ratio: float) -> dict[str, float]:
    """Each joint's threshold in ``step`` (:attr:`Step.thresholds`); ``stop_ratio`` times its
    floor in a step of a run file written before the thresholds were calibrated."""
    return {j: step.thresholds.get(j, stop_ratio * step.floors[j]) for j in step.residuals}


def excess_ratios(step: Step, stop_ratio: float) -> dict[str, float]:
    """Each joint's residual over its threshold in ``step`` (above 1: it stands out)."""
    limits = thresholds(step, stop_ratio)
    return {j: step.residuals[j] / max(limits[j], 1e-300) for j in step.residuals}


def standing_summary(step: Step, neighbours: Callable[[str], Iterable[str]],
                     stop_ratio: float) -> str | None:
    """One sentence on what stands out in ``step``: the joint that stands out most, how many
    others stand out and how many of those are its neighbours (``neighbours(joint)``: the
    joints sharing a plate with it), which may stand out only through it; None when no joint
    stands out."""
    excess = excess_ratios(step, stop_ratio)
    standing = sorted((j for j in excess if excess[j] > 1.0), key=excess.get, reverse=True)
    if not standing:
        return None
    first, others = standing[0], standing[1:]
    text = f"{first} stands out most ({excess[first]:.1f} times its threshold)"
    if not others:
        return text + "; no other joint stands out"
    near = [j for j in others if j in set(neighbours(first))]
    text += (f"; {len(others)} other{'s' if len(others) > 1 else ''} stand"
             f"{'' if len(others) > 1 else 's'} out")
    if not near:
        return text + ", none sharing a plate with it"
    return (f"{text}, {len(near)} of them sharing a plate with it: a joint next to a wrong one "
            f"can stand out only through it, so the updating corrects {first} first and "
            "localises again")


def _candidates(step: Step, settings: Updating, corrected: Collection[str],
                exhausted: Collection[str]) -> tuple[list[str], bool]:
    """Joints to try next and whether they are re-corrections (rule steps 2 and 5).

    A corrected joint that still stands out once its correction no longer lowers the cost
    around it has been given what its data say: the thresholds are calibrated for joints whose
    value the data did not choose, and a fitted joint's residual is not one of them. It no
    longer keeps the loop from its re-corrections, nor from converging; an uncorrected joint
    standing out that no correction helps does (status 1)."""
    excess = excess_ratios(step, settings.stop_ratio)
    by_excess = sorted(step.residuals, key=excess.get, reverse=True)
    standing = [j for j in by_excess if excess[j] > 1.0]
    if any(j not in exhausted for j in standing):
        return [j for j in standing if j not in exhausted], False
    if any(j not in corrected for j in standing):
        return [], False
    return [j for j in by_excess if j in corrected and j not in exhausted], True


def _apart(problem: ModifiedProblem, candidates: Iterable[str]) -> list[str]:
    """The first candidate and, in order, every later one whose neighbourhood shares no joint
    with the neighbourhoods already taken: corrections far enough apart not to see each other,
    made in one step (each judged on its own neighbourhood) before one localisation."""
    taken, covered = [], set()
    for joint in candidates:
        around = set(problem.neighbourhood(joint)[0])
        if not taken or covered.isdisjoint(around):
            taken.append(joint)
            covered |= around
    return taken


def update_joints(problem: ModifiedProblem, settings: Updating, noise: float = 0.0,
                  start: Sequence[Step] | None = None,
                  on_step: Callable[[Step], object] | None = None,
                  on_correct: Callable[[int, str, bool], object] | None = None) -> UpdateResult:
    """The localisation–correction loop (the rule in the module docstring).

    Parameters
    ----------
    problem : updating.inverse.cost.ModifiedProblem
    settings : assembly.settings.Updating
        ``bounds``, ``identify``, ``max_steps``, ``stop_ratio``, ``significance``,
        ``min_decrease``.
    noise : float
        Measurement noise level used for the floors.
    start : sequence of Step, optional
        Finished steps of an earlier run to continue from (resume). The loop's state is a
        function of its finished steps only, so a resumed run ends where an uninterrupted one
        does.
    on_step : callable, optional
        Called with each finished :class:`Step` (to save progress).
    on_correct : callable, optional
        Called with ``(step number, joint, recorrection)`` before each correction (progress).

    Returns
    -------
    UpdateResult
    """
    steps = list(start or [])
    if not steps:
        steps.append(localise(problem, problem.initial_parameters(), noise=noise,
                              settings=settings))
        if on_step:
            on_step(steps[-1])
    if not steps[-1].misfits:  # a run file written before steps carried per-plate misfits
        misfits = problem.evaluate(steps[-1].parameters).misfits
        steps[-1] = dataclasses.replace(steps[-1], misfits=misfits)
    corrected = {j for s in steps for j in s.corrected}
    exhausted = set()
    status = 2
    while len(steps) - 1 < settings.max_steps:
        current = steps[-1]
        candidates, recorrection = _candidates(current, settings, corrected, exhausted)
        if not candidates:
            status = 0 if recorrection else 1
            break
        batch = candidates[:1] if recorrection else _apart(problem, candidates)
        accepted = {}  # joint -> (its parameters, interval), in the batch's order
        for joint in batch:
            if on_correct:
                on_correct(len(steps), joint, recorrection)
            parameters, interval, trial = correct_joint(problem, current.parameters, joint,
                                                        settings.bounds, settings.identify)
            before = problem.neighbourhood_cost(joint, current.residuals, current.misfits)
            after = problem.neighbourhood_cost(joint, trial.residuals, trial.misfits)
            # a correction that buys a lower misfit with a larger residual of the joint's own
            # law fits the measurement noise of a few plates, not a modelling error
            fits_noise = trial.residuals[joint] >= current.residuals[joint]
            if before - after < settings.min_decrease * before or fits_noise:
                exhausted.add(joint)
            else:
                accepted[joint] = (parameters[joint], interval)
        if not accepted:
            continue
        parameters = JointParameters.of(
            {**current.parameters, **{joint: values for joint, (values, _) in accepted.items()}})
        first, *others = accepted
        step = localise(problem, parameters, len(steps), first, accepted[first][1], noise,
                        recorrection, {j: accepted[j][1] for j in others}, settings)
        exhausted.clear()
        corrected.update(accepted)
        steps.append(step)
        if on_step:
            on_step(step)
    return finished_result(problem, steps, status, settings, noise)


def finished_result(problem: ModifiedProblem, steps: Sequence[Step], status: int,
                    settings: Updating, noise: float = 0.0) -> UpdateResult:
    """The :class:`UpdateResult` of a loop that ended with ``status`` after ``steps`` (also
    of a finished run read back from its run file, without running the loop again), with the
    confidence interval of every corrected joint at ``settings.confidence``, calibrated
    against the stated ``noise`` (:func:`updating.inverse.confidence.confidence_intervals`).

    The intervals are those of the final values, every other joint at its own: an interval
    recorded when a joint was corrected is stale once its neighbours have moved.
    """
    final = steps[-1].parameters
    corrected = sorted({j for s in steps for j in s.corrected})
    misfit = steps[-1].e_mes / len(problem.frequencies)
    intervals, more = (confidence_intervals(problem, final, corrected, noise, misfit,
                                            settings.confidence, settings.bounds,
                                            settings.identify)
                       if corrected else ({}, {}))
    return UpdateResult(tuple(steps), status, _message(status, steps[-1], settings), final,
                        intervals, more)


def _message(status: int, last: Step, settings: Updating) -> str:
    """:data:`TERMINATION_MESSAGES` of ``status``, followed by the joints that still stand out
    of their thresholds and how far: for status 1, those whose corrections were undone; for
    status 0, corrected joints whose data have been fitted (:func:`_candidates`)."""
    message = TERMINATION_MESSAGES[status]
    if status not in (0, 1):
        return message
    excess = excess_ratios(last, settings.stop_ratio)
    standing = sorted((j for j in excess if excess[j] > 1.0), key=excess.get, reverse=True)
    if not standing:
        return message
    shown = ", ".join(f"{j} {excess[j]:.2f}" for j in standing[:5])
    more = f" and {len(standing) - 5} more" if len(standing) > 5 else ""
    if status == 0:
        return (f"{message}; corrected joints still above the thresholds of uncorrected ones, "
                f"by: {shown}{more}, where a correction no longer lowers the cost")
    return (f"{message} (still above their thresholds, by: {shown}{more}; "
            "their corrections were undone)")


def _neighbourhood_interval(local: JointCorrection, grid: np.ndarray,
                            value: float) -> tuple[float, float]:
    """The scanned log10 k whose *neighbourhood* cost is within :data:`FLAT` of its minimum
    (:func:`flat_interval`; ``local`` is the joint's
    :class:`updating.inverse.correction.JointCorrection`).

    The joint's neighbourhood, not the global :math:`E_{mod}^2`: in a large structure one
    joint's change is a small fraction of the global cost, and a range judged against it
    spans decades however sensitive the joint is."""
    costs = np.array([local.neighbourhood_cost(log10_stiffness=float(v)) for v in grid])
    best = int(np.argmin(costs))
    at_value = local.neighbourhood_cost(log10_stiffness=value)
    return flat_interval(grid, costs, best, value, min(at_value, float(costs[best])))
