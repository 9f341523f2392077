r"""Calibrated confidence intervals on identified joint parameters: inversion of a score test.

The parameters are each corrected joint's log10 k and, when ``[updating] identify`` asks for
them, its loss factor and line mass (below, :math:`\theta` is any of them).

A corrected joint's :math:`\hat\theta = \log_{10}\hat k` minimises :math:`E_{mod}^2`, a quadratic
form in the measured data. With noise in the data that estimator is biased (by 0.4 decade for
the stiff joint of ``cases/four_plates.toml`` at ±10 % noise, more than its spread), so an
interval centred on it, or a bootstrap around it, misses the truth far more often than its
level says. The interval here is a Neyman construction, calibrated at every candidate value
whatever the bias:

* **Statistic.** At a candidate :math:`v` for the joint (its neighbours' corrected values
  :math:`\hat\nu` fixed), the score :math:`U(v) = \partial E_{mod}^2/\partial\theta` at the
  minimising interface unknowns (by the envelope theorem, the derivative of the quadratic form
  alone: :math:`U = \sum_f y_f^HM'_fy_f`, :math:`y_f` the joint's residual samples). With
  corrected neighbours it is the *efficient* score
  :math:`U_\theta - S_{\theta\nu}S_{\nu\nu}^{-1}U_\nu` (:math:`S` the Hessian of the observed
  cost at the identified values), insensitive to first order to the neighbours' own errors.
* **Its distribution at v.** The model with the joint at :math:`v` predicts the measured
  values :math:`p(v)`; the data are redrawn as :math:`p(v)(1 + e)` with the noise model
  (uniform :math:`\pm\varepsilon` as stated in ``[measurement] noise``, else Gaussian of the
  misfit left at the optimum) and the statistic is computed for each redraw. Everything goes
  through condensations at the identified values
  (:class:`solver.condensation.JointCondensation`): a redraw changes the measurement rows'
  offsets only, which move the joints' samples linearly (:math:`y_0 + D\,\delta\tilde u`,
  with :math:`D` from the same solves as the condensation), so one candidate costs one dense
  solve of the joints' sample size per frequency, for all redraws at once.
* **Interval.** :math:`v` is accepted when the observed statistic lies between the
  :math:`(1-L)/2` and :math:`(1+L)/2` quantiles of the redrawn ones. The accepted run around
  the estimate is found by walking out from it in steps of :data:`STEPS` and locating each
  end where the acceptance margin vanishes (:mod:`updating.inverse.accepted_run`). A run that
  reaches a bound of ``[updating] bounds`` is reported one-sided (``>= x`` near-rigid, ``<= x``
  near-hinge), its other end unchanged: the statement then holds at level :math:`L` or more (a
  one-sided test chosen *because* the run reached the bound would not: the choice depends on
  the data); a run that reaches both is "not identifiable within the bounds".

Every candidate's redraws use the same noise draws (common random numbers), so the accepted set
changes smoothly with :math:`v`. The model's discretisation error biases the estimate
systematically, which no redraw of the noise covers: the estimate's shift when the data are moved
by minus that error (:meth:`ScoreTest.discretisation_shift`) is added to the accepted run's
half-width in quadrature (with exact Levy data, 8.6e-5 decade against a run 1.1e-4 wide and an
estimate 7.8e-5 off the truth; with ±10 % noise it changes the ends by a few per cent of the
width). Coverage is measured in ``bench/bench_confidence.py``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from assembly.types import JointParameters
from solver.condensation import JointCondensation
from updating.inverse.accepted_run import accepted_start, run_end
from updating.inverse.cost import PARAMETER_BOUNDS, SMALLEST_MASS, channel_parameters

if TYPE_CHECKING:
    from solver.channels import Channel
    from solver.interface import Block, InterfaceFactor
    from updating.inverse.correction import JointCorrection
    from updating.inverse.cost import ModifiedProblem

__all__ = ["NoiseModel", "ConfidenceInterval", "ScoreTest", "confidence_interval",
           "confidence_intervals", "noise_model", "REDRAWS"]

REDRAWS = 200
"""Redraws of the noise per candidate value: the 5 % and 95 % quantiles of 200 draws are within
about 0.015 in probability of the exact ones (binomial standard error)."""

STEPS = {"log10_stiffness": (0.1, 0.01), "loss_factor": (0.01, 0.001), "mass": (0.1, 0.01)}
"""Per parameter, the step of the walk out from the estimate and the resolution of the ends
(the line mass's relative to its value: it spans decades). The accepted run must be connected
at the step's resolution: far from the data, where the score has no power, the test accepts
again, and that region is not joined to the run."""
DERIVATIVE_STEP = 1e-6  # decade, central differences of the channel weights (exact to ~1e-11)
HESSIAN_FRACTION = 0.1  # of the walk step: central differences of the observed scores


def _steps(name: str, value: float) -> tuple[float, float]:
    """The walk step and the end resolution of parameter ``name`` at ``value``."""
    walk, resolution = STEPS[name]
    if name == "mass":
        scale = max(value, SMALLEST_MASS)
        return walk * scale, resolution * scale
    return walk, resolution


@dataclass(frozen=True)
class NoiseModel:
    """Relative noise on every measured value: ``w (1 + e)``, ``e`` uniform on
    ``[-level, level]`` (``kind = "uniform"``) or Gaussian of standard deviation ``level``."""

    kind: str
    level: float
    source: str  # "stated" or "estimated from the misfit at the optimum"

    @property
    def deviation(self) -> float:
        """Relative standard deviation of one value."""
        return self.level / math.sqrt(3.0) if self.kind == "uniform" else self.level

    def draws(self, rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
        if self.kind == "uniform":
            return rng.uniform(-self.level, self.level, shape)
        return rng.normal(0.0, self.level, shape)

    @property
    def description(self) -> str:
        if self.kind == "uniform":
            return f"uniform ±{100 * self.level:.3g} % noise ({self.source})"
        return f"Gaussian {100 * self.level:.3g} % noise ({self.source})"


def noise_model(stated: float, misfit: float) -> NoiseModel:
    r"""The noise the intervals are calibrated against.

    ``stated`` is ``[measurement] noise`` (uniform half-width, relative), ``misfit`` the
    :math:`E_{mes}^2` left at the identified values per frequency (a relative mean square:
    each frequency's term is normalised by its own data). The stated noise
    is used unless the misfit shows more than it (standard deviation
    :math:`\sqrt{E_{mes}^2} > \varepsilon/\sqrt3`: noise-free data leave the discretisation
    error, a model error leaves more); then a Gaussian of that size, and the report says so.
    """
    sigma = math.sqrt(max(misfit, 0.0))
    if stated > 0.0 and stated / math.sqrt(3.0) >= sigma:
        return NoiseModel("uniform", stated, "stated")
    return NoiseModel("gaussian", max(sigma, np.finfo(float).eps),
                      "estimated from the misfit at the optimum")


@dataclass(frozen=True)
class ConfidenceInterval:
    """The interval of one joint parameter (``parameter``: log10 k, loss factor or line mass)
    at ``level``.

    ``kind`` is ``"two-sided"`` (``low``, ``high``), ``"lower"`` (``>= low``: only a lower bound,
    a near-rigid joint), ``"upper"`` (``<= high``: a near-hinge) or ``"none"`` (every value in
    the bounds is accepted); an unbounded side is None.
    """

    low: float | None
    high: float | None
    level: float
    kind: str
    method: str
    parameter: str = "log10_stiffness"

    def to_json(self) -> dict[str, Any]:
        return {"interval": [self.low, self.high], "confidence": self.level,
                "method": self.method, "only": {"lower": "lower bound",
                                                "upper": "upper bound"}.get(self.kind)}

    def holds(self, value: float, tolerance: float = 0.0) -> bool:
        """Whether ``value`` lies in the interval widened by ``tolerance`` on each side (an
        unbounded side holds everything)."""
        return ((self.low is None or self.low - tolerance <= value)
                and (self.high is None or value <= self.high + tolerance))

    def span(self, bounds: tuple[float, float]) -> tuple[float, float]:
        """``(low, high)`` with an unbounded side at the bound (to shade a figure)."""
        return (bounds[0] if self.low is None else self.low,
                bounds[1] if self.high is None else self.high)

    @property
    def brief(self) -> str:
        """``[low, high]``, ``>= low``, ``<= high`` or ``none``: a table cell."""
        if self.kind == "two-sided":
            return f"[{self.low:.2f}, {self.high:.2f}]"
        if self.kind == "lower":
            return f">= {self.low:.2f}"
        if self.kind == "upper":
            return f"<= {self.high:.2f}"
        return "none"

    @property
    def text(self) -> str:
        pct = f"{100 * self.level:g} %"
        fmt = ".2f" if self.parameter == "log10_stiffness" else ".3g"
        if self.kind == "two-sided":
            return (f"{pct} confidence interval [{self.low:{fmt}}, {self.high:{fmt}}]")
        if self.kind == "lower":
            return f"{pct} confidence: >= {self.low:{fmt}} (only a lower bound is identifiable)"
        if self.kind == "upper":
            return (f"{pct} confidence: <= {self.high:{fmt}} (only an upper bound is "
                    "identifiable)")
        return f"not identifiable within the bounds at {pct} confidence"


def _weight_derivatives(condensation: JointCondensation, frequency: _TestedFrequency,
                        thetas: Mapping[tuple[str, str], float], key: tuple[str, str]
                        ) -> list[np.ndarray | None]:
    r""":math:`\partial M/\partial\theta` for the parameter ``key`` = (joint, name): 2 x 2
    coefficients for each of the joint's channels, None for the others, by central
    differences of :math:`M(c(\theta))`."""
    h = DERIVATIVE_STEP
    plus = frequency.channel_values({**thetas, key: thetas[key] + h})
    minus = frequency.channel_values({**thetas, key: thetas[key] - h})
    return [(condensation.weight_matrix(w, a, x) - condensation.weight_matrix(w, b, x)) / (2 * h)
            if ch.name == key[0] else None
            for ch, w, a, b, x in zip(frequency.channels, condensation.weights, plus, minus,
                                      condensation.crossovers)]


class ScoreTest:
    """The score statistic of one identified parameter at candidate values, for the observed
    data and for redrawn data (see the module docstring).

    Parameters
    ----------
    problem : updating.inverse.cost.ModifiedProblem
    parameters : dict
        The identified parameters (every joint).
    target : (str, str)
        ``(joint, name)``, name ``"log10_stiffness"``, ``"loss_factor"`` or ``"mass"``.
    group : sequence of (str, str)
        The identified parameters re-estimated with it (nuisances): those of the corrected
        joints of its neighbourhood, ``target`` included.
    corrections, direct : optional
        The joints' :class:`updating.inverse.correction.JointCorrection` and the model
        response's factors at ``parameters`` (default: asked of ``problem``).
    """

    def __init__(self, problem: ModifiedProblem, parameters: Mapping[str, Mapping[str, float]],
                 target: tuple[str, str], group: Sequence[tuple[str, str]],
                 corrections: Mapping[str, JointCorrection] | None = None,
                 direct: Mapping[float, InterfaceFactor] | None = None) -> None:
        self.target = target
        self.group = [target] + [k for k in group if k != target]
        self.values = {key: parameters[key[0]][key[1]] for key in self.group}
        joints = list(dict.fromkeys(joint for joint, _ in self.group))
        # the final re-corrections condensed every corrected joint at these parameters
        corrections = [(corrections or {}).get(j) or problem.correction(parameters, j)
                       for j in joints]
        direct = direct or problem.direct_factors(parameters)
        self._frequencies = []
        for frequency, freq in problem.frequencies.items():
            system = freq.system
            params = channel_parameters(parameters, system.omega)
            condensation = JointCondensation.combined(
                [c.condensation(frequency) for c in corrections])
            channels = [ch for j in joints for ch in system.channels if ch.name == j]
            data_map = condensation.kept_rows.conj().T * freq.value_scale(problem.r)[None, :]
            own = [ch for ch in system.channels if ch.name == target[0]]
            prediction = JointCondensation(
                direct[frequency], [(ch.load, ch.kinematic, problem.alpha[target[0]],
                                     params[target[0], ch.kind], ch.crossover) for ch in own])
            self._frequencies.append(_TestedFrequency(
                condensation, channels, data_map, prediction, own, np.concatenate(freq.data),
                freq.operators, parameters, system.omega,
                None if freq.discretisation is None else np.concatenate(freq.discretisation)))
        self.sensitivity = self._observed_hessian()
        s = self.sensitivity  # the nuisances' first-order effect, projected out of the score
        self._nuisance = np.linalg.solve(s[1:, 1:], s[1:, 0]) if len(self.group) > 1 else None

    @property
    def frequencies(self) -> list[_TestedFrequency]:
        """Per frequency of the problem, in its order: the condensations, the channels and the
        measured values the test uses."""
        return self._frequencies

    @property
    def data_sizes(self) -> list[int]:
        return [len(f.observed) for f in self._frequencies]

    def _scores(self, thetas: Mapping[tuple[str, str], float], columns: Sequence[np.ndarray],
                redraws: Sequence[tuple[np.ndarray, np.ndarray] | None] | None = None
                ) -> np.ndarray:
        r"""Scores of every group parameter at ``thetas``: an array (group, data sets).

        ``columns[f]`` holds the samples :math:`y_0` of the data sets at frequency ``f``; with
        ``redraws[f]`` = ``(D\,diag(p), e)`` (not None), the data sets are followed by the
        redraws ``columns[f][:, -1] + D diag(p) e_b``: solving for the measured values, when
        they are fewer than the redraws, and then combining is cheaper than solving for every
        redraw.
        """
        def at_frequency(i: int) -> np.ndarray:
            f, y0 = self._frequencies[i], columns[i]
            params = f.channel_values(thetas)
            if redraws is None or redraws[i] is None:
                y = f.condensation.solve_samples(params, y0)
            else:
                response, noise = redraws[i]
                solved = f.condensation.solve_samples(params, np.hstack([y0, response]))
                n = y0.shape[1]
                y = np.hstack([solved[:, :n], solved[:, n - 1:n] + solved[:, n:] @ noise])
            rows = []
            for key in self.group:
                coefficients = _weight_derivatives(f.condensation, f, thetas, key)
                rows.append(np.sum(y.conj() * f.condensation.apply(coefficients, y), 0).real)
            return np.array(rows)

        return sum(at_frequency(i) for i in range(len(self._frequencies)))

    def _observed_hessian(self) -> np.ndarray:
        r""":math:`S_{kl} = \partial U_k/\partial\theta_l` of the observed data at the identified
        values (central differences of the scores)."""
        observed = [f.condensation.y0[:, None] for f in self._frequencies]
        m = len(self.group)
        hessian = np.zeros((m, m))
        for col, key in enumerate(self.group):
            step = HESSIAN_FRACTION * _steps(key[1], self.values[key])[0]
            plus = {**self.values, key: self.values[key] + step}
            minus = {**self.values, key: self.values[key] - step}
            hessian[:, col] = (self._scores(plus, observed)[:, 0]
                               - self._scores(minus, observed)[:, 0]) / (2 * step)
        return 0.5 * (hessian + hessian.T)

    def _efficient(self, scores: np.ndarray) -> np.ndarray:
        """The target's score freed from the nuisances' to first order (rows: the group's
        scores)."""
        return scores[0] if self._nuisance is None else scores[0] - self._nuisance @ scores[1:]

    def discretisation_shift(self) -> float:
        r"""How far the estimate moves when the model's own prediction :math:`p(\hat\theta)` is
        moved by minus its discretisation error at the measured points (:math:`\delta = w^+ -
        w_h` of the enriched solve,
        :meth:`updating.inverse.cost.ModifiedProblem.synthetic_data`): one Newton step on the
        efficient score, :math:`-(U(\hat\theta; p - \delta) - U(\hat\theta; p))/S`. The
        error is systematic, not noise, so the noise's redraws do not cover the bias it gives
        the estimate. Taken on the prediction, not on the data: the score is quadratic in the
        data, and on noisy data the cross term of the noise with :math:`\delta` counted noise
        as bias (the intervals then held the truth in 97-100 of 100 draws at level 0.9). 0 when
        the enriched solve was not made."""
        columns = []
        for f in self._frequencies:
            if f.discretisation is None:
                return 0.0
            base = f.samples(f.predicted(self.values))
            columns.append(np.column_stack([base, base - f.data_map @ f.discretisation]))
        scores = self._efficient(self._scores(self.values, columns))
        s = self.sensitivity
        curvature = s[0, 0] - (0.0 if self._nuisance is None else s[0, 1:] @ self._nuisance)
        return float((scores[0] - scores[1]) / curvature) if curvature != 0.0 else 0.0

    def separation(self, a: float, b: float, deviation: float) -> float:
        r"""How many noise standard deviations apart the model's predictions with the joint
        at ``a`` and at ``b`` are, all values together:
        :math:`\sqrt{\sum_n|p_n(b) - p_n(a)|^2/(\sigma|p_n(a)|)^2}`. Below one, no test on
        these data tells ``b`` from ``a``."""
        total = 0.0
        for f in self._frequencies:
            pa = f.predicted({**self.values, self.target: a})
            pb = f.predicted({**self.values, self.target: b})
            scale = np.maximum(deviation * np.abs(pa), np.finfo(float).tiny)
            total += float(np.sum(np.abs((pb - pa) / scale) ** 2))
        return math.sqrt(total)

    def statistics(self, value: float, noise: Sequence[np.ndarray]
                   ) -> tuple[float, np.ndarray, float]:
        """Observed statistic, redrawn ones (array) and the noise-free prediction's with the
        joint at ``value``.

        ``noise`` holds per frequency the relative noise ``e`` of every redraw, shape
        (measured values, redraws).
        """
        thetas = {**self.values, self.target: value}
        columns, redraws = [], []
        for f, e in zip(self._frequencies, noise):
            predicted = f.predicted(thetas)
            # a redraw p (1 + e) has samples y0 + D (p - observed) + D diag(p) e: solved through
            # the measured values when they are fewer than the redraws, else redraw by redraw
            y0 = f.condensation.y0
            base = f.samples(predicted)
            response = f.data_map * predicted
            if e.shape[0] < e.shape[1]:
                columns.append(np.column_stack([y0, base]))
                redraws.append((response, e))
            else:
                columns.append(np.column_stack([y0, base, base[:, None] + response @ e]))
                redraws.append(None)
        statistic = self._efficient(self._scores(thetas, columns, redraws))
        return statistic[0], statistic[2:], statistic[1]  # observed, redraws, prediction


@dataclass
class _TestedFrequency:
    """What the score test needs of one measured frequency (built from the problem's
    :class:`updating.inverse.problem_data.FrequencyData`)."""

    condensation: JointCondensation  # the group's channels, at the identified values, r > 0
    channels: list[Channel]
    data_map: np.ndarray  # D: samples per unit change of the measured values
    prediction: JointCondensation  # the target joint's channels in the model response (r = 0)
    own: list[Channel]  # those channels
    observed: np.ndarray
    operators: list[Block]
    parameters: Mapping[str, Mapping[str, float]]
    omega: float
    discretisation: np.ndarray | None  # the model's w+ - w_h at the measured values

    def _values(self, thetas: Mapping[tuple[str, str], float],
                channels: Sequence[Channel]) -> list[complex]:
        """``channels``' parameters with ``thetas`` ``{(joint, name): value}`` set."""
        trial = JointParameters.of(self.parameters)
        for (joint, name), theta in thetas.items():
            trial = trial.with_joint(joint, **{name: theta})
        params = channel_parameters(trial, self.omega)
        return [params[ch.name, ch.kind] for ch in channels]

    def channel_values(self, thetas: Mapping[tuple[str, str], float]) -> list[complex]:
        """The group's channel parameters with ``thetas`` set."""
        return self._values(thetas, self.channels)

    def response(self, thetas: Mapping[tuple[str, str], float]) -> np.ndarray:
        """Interface unknowns of the model response with ``thetas`` set (the nuisances are at
        their identified values: only the target joint's channels change)."""
        return self.prediction.interface(self._values(thetas, self.own))

    def samples(self, values: np.ndarray) -> np.ndarray:
        r"""The samples :math:`y_0 + D\,(v - \tilde u)` of measured values ``v`` (linear in
        them: the condensation's response to the measurement rows' offsets)."""
        return self.condensation.y0 + self.data_map @ (values - self.observed)

    def predicted(self, thetas: Mapping[tuple[str, str], float]) -> np.ndarray:
        """The model's values at the measured points with ``thetas`` set."""
        s = self.response(thetas)
        return np.concatenate([op.residual(s) for op in self.operators])


def confidence_interval(problem: ModifiedProblem, parameters: Mapping[str, Mapping[str, float]],
                        target: tuple[str, str], group: Sequence[tuple[str, str]],
                        noise: NoiseModel, level: float, stiffness_bounds: tuple[float, float],
                        redraws: int = REDRAWS, seed: int = 0, test: ScoreTest | None = None,
                        expected: bool = False) -> ConfidenceInterval:
    r"""The ``level`` confidence interval of the parameter ``target`` = (joint, name) (see the
    module docstring) within its bounds (``stiffness_bounds`` for log10 k).

    ``noise`` is a :class:`NoiseModel`; ``group`` the identified parameters of the corrected
    joints of its neighbourhood; ``test`` its :class:`ScoreTest`, if already built.

    ``expected``: the problem's data are noise-free (a plan's: the model's own prediction),
    and the interval wanted is that of typical noisy data. The statistic is quadratic in the
    data, so noise shifts it on average (:math:`U` of the redraws around :math:`p(v)` centres
    on :math:`U(p(v)) + b(v)`, not on :math:`U(p(v))`): noise-free data compared with noisy
    redraws can reject the very value they were made with (measured: the 6 x 6 grid's
    ``V1_1``, model 2.00, got [1.63, 1.97]). The observed statistic is then moved by the
    redraws' median shift at each candidate, :math:`U_{obs} - U(p(v)) +
    \mathrm{median}_b\,U_b`, so that the model's value sits at the centre of its redraws.
    """
    test = test or ScoreTest(problem, parameters, target, group)
    bounds = tuple(PARAMETER_BOUNDS.get(target[1], stiffness_bounds))
    walk, resolution = _steps(target[1], parameters[target[0]][target[1]])
    rng = np.random.default_rng(seed)
    draws = [noise.draws(rng, (n, redraws)) for n in test.data_sizes]
    tail = (1.0 - level) / 2.0
    cache = {}

    def margin(v: float) -> tuple[float, int, float]:
        """How far inside the redraws' central range the observed statistic lies at ``v``, in
        units of that range: >= 0 accepted; negative below it (-) or above it (+) rejected
        (the sign, returned second, says which side)."""
        key = round(float(v), 9)
        if key not in cache:
            observed, redrawn, noise_free = test.statistics(key, draws)
            if expected:
                observed += np.median(redrawn) - noise_free
            low, middle, high = np.quantile(redrawn, [tail, 0.5, 1.0 - tail])
            width = max(high - low, np.finfo(float).tiny)
            cache[key] = (min(observed - low, high - observed) / width,
                          -1 if observed < low else 1 if observed > high else 0,
                          (observed - middle) / width)
        return cache[key]

    start = min(max(parameters[target[0]][target[1]], bounds[0]), bounds[1])
    inside = accepted_start(start, margin, bounds, walk, resolution)
    method = f"score-test inversion, {redraws} redraws of {noise.description}"
    if inside is None:
        return ConfidenceInterval(None, None, level, "none", method, target[1])

    def indistinguishable(a: float, b: float) -> bool:
        return test.separation(a, b, noise.deviation) < 1.0

    low, low_side = run_end(inside, -1, margin, bounds, indistinguishable, walk, resolution)
    high, high_side = run_end(inside, +1, margin, bounds, indistinguishable, walk, resolution)
    # the discretisation's systematic shift, which the redraws do not cover, added to the
    # run's half-width in quadrature (random and systematic parts of one uncertainty)
    half = 0.5 * (high - low)
    widen = math.hypot(half, test.discretisation_shift()) - half
    low, high = max(low - widen, bounds[0]), min(high + widen, bounds[1])
    if low_side == 0 and high_side == 0:
        return ConfidenceInterval(None, None, level, "none", method, target[1])
    # One bound only: the end of the two-sided run is kept, so the statement misses only
    # when the two-sided test rejects the truth (probability 1 - level at most). A one-sided
    # test chosen after seeing that the run reaches a bound would miss more often than its
    # level (the choice itself depends on the data).
    if high_side == 0:
        return ConfidenceInterval(low, None, level, "lower", method, target[1])
    if low_side == 0:
        return ConfidenceInterval(None, high, level, "upper", method, target[1])
    return ConfidenceInterval(low, high, level, "two-sided", method, target[1])


def confidence_intervals(problem: ModifiedProblem, parameters: Mapping[str, Mapping[str, float]],
                         joints: Sequence[str], stated_noise: float, misfit: float, level: float,
                         bounds: tuple[float, float], identify: Sequence[str] = ("stiffness",),
                         redraws: int = REDRAWS, seed: int = 0
                         ) -> tuple[dict[str, ConfidenceInterval],
                                    dict[tuple[str, str], ConfidenceInterval]]:
    """``({joint: log10 k interval}, {(joint, name): interval})`` of the corrected ``joints``
    at ``parameters``; the loss factors' and line masses' when ``identify`` holds
    ``"damping"`` and ``"mass"``.

    ``misfit`` is :math:`E_{mes}^2` per frequency there (:func:`noise_model`). The nuisances
    of each test are the identified parameters of the corrected joints of its neighbourhood:
    those its data also determine, and only those, so an interval costs the same in a
    structure of any size.
    """
    noise = noise_model(stated_noise, misfit)
    names = (["log10_stiffness"] + (["loss_factor"] if "damping" in identify else [])
             + (["mass"] if "mass" in identify else []))
    # Every test is built first, from the joints' condensations and one factorisation of the
    # model response; the updating problem's own factorisation is released before that one
    # is made, so that a large structure holds one at a time.
    corrections = {j: problem.correction(parameters, j) for j in joints}
    problem.release_factors()
    direct = problem.direct_factors(parameters)
    tests = {}
    def identified(joint: str) -> list[str]:  # a line mass only where the joint has one
        return [n for n in names if n != "mass" or problem.has_line_mass(joint)]

    for joint in joints:
        around = problem.neighbourhood(joint)[0]
        group = [(j, name) for j in joints if j in around for name in identified(j)]
        for name in identified(joint):
            tests[joint, name] = ScoreTest(problem, parameters, (joint, name), group,
                                           corrections, direct)
    del direct, corrections
    stiffness, more = {}, {}
    for (joint, name), test in tests.items():
        interval = confidence_interval(problem, parameters, (joint, name), test.group, noise,
                                       level, bounds, redraws, seed, test)
        if name == "log10_stiffness":
            stiffness[joint] = interval
        else:
            more[joint, name] = interval
    return stiffness, more
