"""Guard rails of a description: what a double-precision VTCR solve cannot take, found before
any solve (ray counts below the resolution rule or past :data:`MAX_RAYS_PER_PLATE`, magnitudes
out of range, point forces on an edge, measurement grids in the wrong unit, a solve larger than
the memory). Every entry point runs them: the commands and the library calls alike
(``docs/accuracy.md``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import networkx as nx

from assembly.case import Case
from assembly.errors import DescriptionError, Issue, format_path
from assembly.lines import members_coplanar
from solver.in_plane import coplanar_closure, in_plane_edge_conditions, in_plane_plates
from solver.line_ends import SINGULAR_END_REACH
from solver.problems import plate_problems, plate_ray_counts
from solver.rays import RayCounts, automatic_ray_counts
from solver.sizing import available_memory, estimate_size

__all__ = ["description_issues", "check_description", "UNDER_RESOLVED", "UNDER_RESOLVED_WARNING",
           "MAX_RAYS_PER_PLATE", "MAX_GRID_POINTS", "KIRCHHOFF_WAVELENGTH"]


UNDER_RESOLVED = 0.6
"""Ray counts below this fraction of the resolution rule are an error.

The rule (:func:`solver.rays.automatic_ray_counts`, resolution 1) gives field errors of
3e-5 to 8e-4 on ``cases/single_plate``, ``two_plates`` and ``four_plates``; scaled by 0.8 the
errors are 0.7 %, 18 % and 21 %, by 0.6 already 7 %, 26 % and 80 %, by 0.5 75-96 % (relative L2
of w on a 2 cm grid against resolution 2). Lowering one family alone to 0.6 of its count gives
up to 49 % (interior) and 13 % (evanescent edge rays). Below 0.6 the rays do not resolve the
bending wavelength: the result is not a coarse approximation but a wrong field.
"""


UNDER_RESOLVED_WARNING = 0.85
"""Ray counts below this fraction of the rule (but above :data:`UNDER_RESOLVED`) warn: errors
of a few per cent to 20 % near a resonance (see :data:`UNDER_RESOLVED`)."""


MAX_RAYS_PER_PLATE = 1500
"""Most ray unknowns per plate that a description may ask for.

Single 0.5 x 0.4 m steel plate, 1 mm, simply supported (one dense solve, one thread):
1098 unknowns at 30 kHz take 2.5 s with condition estimate 2e19; 1988 at 100 kHz take 9 s
(0.8 GB) with 2e20, past :data:`solver.errors.CONDITION_WARNING`, where double precision starts
to lose the field; updating repeats such solves for every joint and step.
"""


MAX_GRID_POINTS = 100_000
"""Most points of the measurement grid on one plate (``[measurement] spacing``): a laser
vibrometer scan has hundreds to a few thousands; a finer grid is most likely a unit mistake
(millimetres for metres) and would make simulating and sampling the field crawl."""


EDGE_FORCE_DISTANCE = 1e-4
"""Closest a point force may be to an edge, as a fraction of the plate's smaller side. On the
simply supported 0.5 x 0.4 m plate at 155 Hz the error (and its estimate) is 27 % (1.0) at
1 mm, 289 % (1.2) at 0.1 mm and 720 % (0.58) at 40 um; at 10 um the estimate catches a
quarter of the error, at 1 um a thirtieth."""


SI_PLAUSIBLE_SIZE = 100.0
"""A plate side above this many metres is more likely in millimetres: warned, not refused,
unless the materials are in SI units (:data:`SI_YOUNG_MODULUS`): then refused."""

SI_YOUNG_MODULUS = 1e7
"""A Young's modulus above this is in pascals (metals 4e10-4e11 Pa, polymers 1e9 Pa); in a
consistent millimetre system (N, mm, t, s) it is in MPa (steel 2.1e5)."""

LOG10_RANGE = 100.0
"""Decades either side of 1 allowed for a plate's bending stiffness (N m) and mass per area
(kg/m^2): steel sheet to concrete slab span 1e-3..1e9 and 1..1e3; beyond 1e100 the fourth
powers and exponentials of the solve overflow."""


LOW_FREQUENCY_KAPPA_R = 0.3
r"""Smallest :math:`\kappa_0R_{max}` accepted (plate half-diagonal in radians of bending wave).
On the simply supported 0.5 x 0.4 m plate the error is 4e-3 at 0.3 (0.3 Hz), 3-27 % at 0.2
and 14 % at 0.1, whatever the resolution: the rays of a plate that small against the
wavelength are nearly linearly dependent and cannot carry a quasi-static field."""


HIGH_FREQUENCY_KAPPA_R = 1e4
r"""Largest :math:`\kappa_0R_{max}` looked at further (the ray-count limit
:data:`MAX_RAYS_PER_PLATE` refuses far smaller ones; this only keeps the counts finite)."""


KIRCHHOFF_WAVELENGTH = 6.0
"""Kirchhoff (thin-plate) theory holds while the bending wavelength exceeds this many
thicknesses (the usual lambda > 6 h); shorter waves feel shear and rotary inertia (Mindlin)."""


_FAMILIES = ("interior", "edge_propagating", "edge_evanescent")


_FAMILY_NAMES = {"interior": "interior", "edge_propagating": "propagating edge",
                 "edge_evanescent": "evanescent edge"}


_Loc = tuple[str | int, ...]  # where an issue is: a field path, or ("--frequency",)


def _family_counts(counts: RayCounts, family: str) -> tuple[int, ...]:
    value = getattr(counts, family)
    return (value,) if isinstance(value, int) else tuple(value)


def _short(counts: RayCounts, floor: RayCounts, families: Iterable[str]) -> list[str]:
    """Families of ``counts`` with a count below ``floor`` (per edge for edge families)."""
    return [f for f in families
            if any(u < m for u, m in zip(_family_counts(counts, f), _family_counts(floor, f)))]


def _shown(counts: RayCounts, family: str) -> str:
    values = _family_counts(counts, family)
    return str(values[0]) if len(set(values)) == 1 else "/".join(map(str, values))


def _counts_text(counts: RayCounts, rule: RayCounts, families: Iterable[str]) -> str:
    return ", ".join(f"{_shown(counts, fam)} {_FAMILY_NAMES[fam]} (rule: {_shown(rule, fam)})"
                     for fam in families)


def _millimetres_against_pascals(case: Case) -> tuple[_Loc, str] | None:
    """The error of a description whose lengths look like millimetres (a plate side above
    :data:`SI_PLAUSIBLE_SIZE`) while its materials are in pascals: every derived quantity
    is then wrong by powers of 1000, and the other checks' messages (ray counts, memory) would
    point at the wrong fix. None when the units are consistent."""
    largest = max(max(plate.size) for plate in case.plates.values())
    moduli = [m.young_modulus for m in case.materials.values()]
    if largest <= SI_PLAUSIBLE_SIZE or max(moduli) <= SI_YOUNG_MODULUS:
        return None
    return (("plates",), f"the largest plate side is {largest:g} while Young's moduli are in "
            f"pascals ({max(moduli):.3g}): the lengths look like millimetres against SI "
            "materials; give sizes, thicknesses, positions and spacings in m (or every value "
            "in N, mm, t, s: E in MPa, density in t/mm^3)")


def _scale_issues(
    case: Case, frequencies: Sequence[float], location: Callable[[float], _Loc],
) -> tuple[list[tuple[_Loc, str]], list[tuple[_Loc, str]]]:
    r"""Magnitudes a double-precision Trefftz solve cannot take, found before computing them.

    Computed in logarithms, so that absurd inputs (a thickness of 1e300, a frequency of
    1e-300) are reported rather than overflowing: the bending stiffness and the mass per area
    must stay within :data:`LOG10_RANGE` decades of 1, and at every frequency each plate's
    :math:`\kappa_0R_{max}` (half-diagonal in radians of bending wave) must lie between
    :data:`LOW_FREQUENCY_KAPPA_R` and :data:`HIGH_FREQUENCY_KAPPA_R`. A plate thicker than a
    tenth of its smaller side warns (thin-plate theory needs h much smaller than the plate).
    """
    errors: list[tuple[_Loc, str]] = []
    warnings: list[tuple[_Loc, str]] = []
    low, high = min(frequencies), max(frequencies)
    largest = max(max(plate.size) for plate in case.plates.values())
    if largest > SI_PLAUSIBLE_SIZE and not _millimetres_against_pascals(case):
        warnings.append((("plates",),
                         f"the largest plate side is {largest:g}: vtcr computes in any "
                         "consistent unit system, but if these are millimetres its unit labels "
                         "(m, Pa, kg/m^3, N/m) do not apply: read lengths in mm, stresses in "
                         "MPa, densities in t/mm^3"))
    for pid, plate in case.plates.items():
        material = case.materials[plate.material]
        log_d = (math.log10(material.young_modulus) + 3.0 * math.log10(plate.thickness)
                 - math.log10(12.0 * (1.0 - material.poisson_ratio**2)))
        log_mass = math.log10(material.density) + math.log10(plate.thickness)
        if abs(log_d) > LOG10_RANGE or abs(log_mass) > LOG10_RANGE:
            errors.append((("plates", pid, "thickness"),
                           f"plate {pid}: bending stiffness E h^3 / (12 (1 - nu^2)) = "
                           f"1e{log_d:.0f} N m and mass per area rho h = 1e{log_mass:.0f} "
                           "kg/m^2 are beyond what a double-precision solve can take; give the "
                           "thickness (m), young_modulus (Pa) and density (kg/m^3) in SI units"))
            continue
        r_max = 0.5 * math.hypot(*plate.size)
        if plate.thickness >= min(plate.size):
            errors.append((("plates", pid, "size"),
                           f"plate {pid}: its side {min(plate.size):g} m is not larger than its "
                           f"thickness {plate.thickness:g} m: not a plate (a 1 um wide plate "
                           "gave a field wrong by 1e14); give the sizes and the thickness in m"))
            continue
        if plate.thickness > 0.1 * min(plate.size):
            warnings.append((("plates", pid, "thickness"),
                             f"plate {pid}: thickness {plate.thickness:g} m is more than a tenth "
                             f"of its smaller side ({min(plate.size):g} m), beyond thin-plate "
                             "(Kirchhoff) theory: shear and rotary inertia are neglected"))
        for f in sorted({low, high}):
            log_kr = (log_mass + 2.0 * math.log10(2.0 * math.pi * f) - log_d) / 4.0 \
                + math.log10(r_max)
            if log_kr < math.log10(LOW_FREQUENCY_KAPPA_R):
                f_min = float(f"{f * (LOW_FREQUENCY_KAPPA_R / 10.0**log_kr) ** 2:.2g}")
                errors.append((location(f),
                               f"plate {pid} at {f:g} Hz: its half-diagonal is "
                               f"{10.0**log_kr / (2 * math.pi):.1g} bending wavelength, far "
                               "below its first resonance, where the ray basis does not "
                               "converge (errors of 10 % and more on a simply supported plate); "
                               f"results cannot be trusted below about {f_min:g} Hz for this "
                               "plate: give frequencies above it"))
            elif log_kr > math.log10(HIGH_FREQUENCY_KAPPA_R):
                errors.append((location(f),
                               f"plate {pid} at {f:g} Hz: its half-diagonal is "
                               f"1e{log_kr - math.log10(2 * math.pi):.0f} bending wavelengths; "
                               "lower the frequency (or check its unit: Hz)"))
    for index, load in enumerate(case.loads):
        if load.kind != "point_force" or load.plate not in case.plates:
            continue
        size = case.plates[load.plate].size
        distance = min(load.at[0], size[0] - load.at[0], load.at[1], size[1] - load.at[1])
        if distance < EDGE_FORCE_DISTANCE * min(size):
            errors.append((("loads", index, "at"),
                           f"the point force on plate {load.plate} is {distance:.2g} m from an "
                           f"edge, closer than {EDGE_FORCE_DISTANCE:g} of the plate's side "
                           f"({EDGE_FORCE_DISTANCE * min(size):.2g} m): the rays cannot follow its "
                           "image in the edge (1 um away, the field was wrong by 3e4 %, and the "
                           "error estimate missed it); move it inside, or model it as an edge "
                           "load"))
    return errors, warnings


def _load_issues(case: Case, need_loads: bool) -> list[tuple[_Loc, str]]:
    """**loads** (if ``need_loads``): a description without loads has a zero response."""
    if need_loads and not case.loads:
        return [(("loads",), "the description has no [[loads]], so its forced response "
                 "is zero (nothing to solve or compare with measurements); add a load, "
                 'e.g. [[loads]] kind = "point_force", plate = "P1", at = [0.1, 0.1], '
                 "amplitude = 1.0")]
    return []


def _grid_issues(case: Case) -> list[tuple[_Loc, str]]:
    """**measurement grid**: more than :data:`MAX_GRID_POINTS` points on a plate is an error,
    named for the first such plate."""
    spacing = case.measurement.spacing
    for pid in case.plates:  # the grid of `vtcr solve` covers every plate
        nx, ny = (max(1, round(length / spacing)) for length in case.plates[pid].size)
        if nx * ny > MAX_GRID_POINTS:
            return [(("measurement", "spacing"),
                     f"spacing {spacing:g} m puts {nx} x {ny} grid points on plate {pid} "
                     f"(more than {MAX_GRID_POINTS}); give the spacing in metres, e.g. "
                     "spacing = 0.05")]
    return []


@dataclass(frozen=True)
class _PlateRays:
    """One plate's ray counts at the checked frequency, and the resolution rule's there."""

    pid: str
    where: str  # the plate, the frequency and the wavelength, as the messages name them
    wavelength: float  # bending wavelength, m
    thickness: float  # m
    rule: RayCounts  # the resolution rule (resolution 1)
    floor: RayCounts  # the rule at UNDER_RESOLVED
    fair: RayCounts  # the rule at UNDER_RESOLVED_WARNING
    used: RayCounts  # the model's counts
    simulated: RayCounts  # the simulated experiment's counts
    own: list[str]  # the families the description's per-plate override sets
    auto: list[str]  # the families the rule sets


def _plate_rays(case: Case, f: float) -> list[_PlateRays]:
    """:class:`_PlateRays` of every plate at frequency ``f``."""
    settings = case.discretisation
    simulation = settings.resolution * case.measurement.resolution
    problems = plate_problems(case, f)
    out = []
    for pid, plate in case.plates.items():
        problem = problems[pid]
        kappa0 = problem.kappa.real
        wavelength = 2.0 * math.pi / kappa0
        lx, ly = plate.size
        override = settings.for_plate(pid)
        own = [fam for fam in _FAMILIES if getattr(override, fam) is not None]
        tau = settings.edge_ratio(pid)
        out.append(_PlateRays(
            pid=pid,
            where=(f"plate {pid} at {f:g} Hz (bending wavelength {wavelength:.3g} m, "
                   f"{lx / wavelength:.1f} x {ly / wavelength:.1f} wavelengths)"),
            wavelength=wavelength,
            thickness=plate.thickness,
            rule=automatic_ray_counts(kappa0, plate.size, 1.0, tau),
            floor=automatic_ray_counts(kappa0, plate.size, UNDER_RESOLVED, tau),
            fair=automatic_ray_counts(kappa0, plate.size, UNDER_RESOLVED_WARNING, tau),
            used=plate_ray_counts(case, pid, problem),
            simulated=plate_ray_counts(case, pid, problem, simulation),
            own=own,
            auto=[fam for fam in _FAMILIES if fam not in own],
        ))
    return out


def _override_issues(
    rays: _PlateRays,
) -> tuple[list[tuple[_Loc, str]], list[tuple[_Loc, str]]]:
    """**ray resolution** of the families a plate's override sets: below
    :data:`UNDER_RESOLVED` of the rule an error naming the override, below
    :data:`UNDER_RESOLVED_WARNING` a warning."""
    errors: list[tuple[_Loc, str]] = []
    warnings: list[tuple[_Loc, str]] = []
    pid, where, used, rule, floor = rays.pid, rays.where, rays.used, rays.rule, rays.floor
    for fam in _short(used, floor, rays.own):
        errors.append((("discretisation", "plates", pid, fam),
                       f"{_shown(used, fam)} {_FAMILY_NAMES[fam]} ray sectors cannot resolve "
                       f"{where}: the resolution rule asks {_shown(rule, fam)} (below "
                       f"{_shown(floor, fam)}, {UNDER_RESOLVED:g} of it, the field is wrong); "
                       f"give {fam} = "
                       f"{max(_family_counts(rule, fam))} or remove the override"))
    for fam in _short(used, rays.fair, rays.own):
        if fam not in _short(used, floor, rays.own):
            warnings.append((("discretisation", "plates", pid, fam),
                             f"{_shown(used, fam)} {_FAMILY_NAMES[fam]} ray sectors for "
                             f"{where}, below the {_shown(rule, fam)} of the resolution "
                             "rule: expect errors of a few per cent near a resonance"))
    return errors, warnings


def _thin_plate_issues(rays: _PlateRays, f: float, f_loc: _Loc) -> list[tuple[_Loc, str]]:
    """**thin-plate theory**: a bending wavelength below :data:`KIRCHHOFF_WAVELENGTH`
    thicknesses warns."""
    if rays.wavelength < KIRCHHOFF_WAVELENGTH * rays.thickness:
        return [(f_loc, f"plate {rays.pid} at {f:g} Hz: the bending wavelength "
                 f"{rays.wavelength:.3g} m is less than {KIRCHHOFF_WAVELENGTH:g} "
                 f"thicknesses ({rays.thickness:g} m), beyond thin-plate "
                 "(Kirchhoff) theory; lower the frequency")]
    return []


def _size_issues(plates: Sequence[_PlateRays], f: float, f_loc: _Loc) -> list[tuple[_Loc, str]]:
    """**size**: more than :data:`MAX_RAYS_PER_PLATE` ray unknowns on a plate is an error, one
    per location (the frequency when the rule itself asks that many, else the resolution)
    naming the first such plate."""
    huge: dict[_Loc, list[tuple[str, str, int]]] = {}
    for rays in plates:
        if rays.used.total > MAX_RAYS_PER_PLATE:
            loc = (f_loc if rays.rule.total > MAX_RAYS_PER_PLATE
                   else ("discretisation", "resolution"))
            huge.setdefault(loc, []).append((rays.pid, rays.where, rays.used.total))
    errors: list[tuple[_Loc, str]] = []
    for loc, found in huge.items():
        _, where, total = found[0]
        others = [p for p, *_ in found[1:]]
        likewise = f"; likewise plate(s) {', '.join(others)}" if others else ""
        f_ok = float(f"{f * (MAX_RAYS_PER_PLATE / total) ** 2:.2g}")  # counts ~ sqrt(f)
        errors.append((loc, f"{where}: the VTCR would need {total} ray unknowns on it, beyond "
                       f"{MAX_RAYS_PER_PLATE} (each dense solve takes seconds to minutes and its "
                       "condition estimate passes 1e20, where double precision loses the "
                       f"field){likewise}; lower the frequency (below about {f_ok:g} Hz) or "
                       "split the plate into smaller plates joined by stiff coplanar joints"))
    return errors


def _resolution_issues(
    case: Case, plates: Sequence[_PlateRays],
) -> tuple[list[tuple[_Loc, str]], list[tuple[_Loc, str]]]:
    """**ray resolution** of the families the rule sets, scaled by ``[discretisation]
    resolution`` (the model) and by ``[measurement] resolution`` too (the simulated
    experiment): below :data:`UNDER_RESOLVED` of the rule an error per setting, below
    :data:`UNDER_RESOLVED_WARNING` a warning, each naming the first such plate."""
    settings = case.discretisation
    scaled: dict[str, list[tuple[str, RayCounts, RayCounts, list[str]]]] = {
        "error": [], "warning": [], "simulation": []}
    for rays in plates:
        used, rule, floor, auto = rays.used, rays.rule, rays.floor, rays.auto
        if _short(used, floor, auto):
            scaled["error"].append((rays.where, used, rule, _short(used, floor, auto)))
        elif _short(used, rays.fair, auto):
            scaled["warning"].append((rays.where, used, rule, _short(used, rays.fair, auto)))
        sim = rays.simulated
        if _short(sim, floor, auto) and case.measurement.resolution < 1.0:
            scaled["simulation"].append((rays.where, sim, rule, _short(sim, floor, auto)))
    fixes = {
        "error": f"give a resolution of at least {UNDER_RESOLVED:g} (1.0 is the rule)",
        "simulation": (f"give a resolution of at least "
                       f"{UNDER_RESOLVED / settings.resolution:.2g} (the simulation multiplies "
                       "it by [discretisation] resolution; the default 1.6 refines the model's "
                       "rays, so that the simulated experiment is not the model itself)"),
    }
    errors: list[tuple[_Loc, str]] = []
    warnings: list[tuple[_Loc, str]] = []
    for kind, loc, value, what in (
            ("error", ("discretisation", "resolution"), settings.resolution, "the model"),
            ("simulation", ("measurement", "resolution"), case.measurement.resolution,
             "the simulated experiment")):
        if scaled[kind]:
            where, counts, rule, families = scaled[kind][0]
            others = len(scaled[kind]) - 1
            more = f"; likewise {others} other plate(s)" if others else ""
            errors.append((loc, f"resolution {value:g} leaves {what} too few rays to resolve "
                           f"{where}: {_counts_text(counts, rule, families)} ray sectors{more}; "
                           + fixes[kind]))
    if scaled["warning"]:
        where, counts, rule, families = scaled["warning"][0]
        warnings.append((("discretisation", "resolution"),
                         f"resolution {settings.resolution:g} gives {where} "
                         f"{_counts_text(counts, rule, families)} ray sectors: expect errors of a "
                         "few per cent near a resonance; 1.0 is the rule"))
    return errors, warnings


def _singular_end_issues(case: Case) -> list[tuple[_Loc, str]]:
    r"""A warning per junction line between non-coplanar plates whose end is a plane of
    symmetry for part of the motion only (:meth:`assembly.Case.singular_ends`: an in-plane
    ``roller`` edge simply supported in bending, say). There the line's loads are log-singular
    at its ends; its members carry logarithmic corner functions there and edge waves reaching
    :data:`solver.line_ends.SINGULAR_END_REACH` times further (``docs/method.md`` section
    10.4), and its line's loads carry their logarithmic terms there, at 30 to 50 times the cost
    of the held line; its field keeps an error of up to about 1.5e-4 in ``w`` and 1e-3
    in-plane against independent finite-element solutions of an L fold and a T junction,
    which the estimate may understate (to 1/4 at the worst measured, where a member hangs on
    the line; the count of the line's Legendre functions has a floor for it,
    :func:`solver.joint_rules.mixed_end_legendre_count`). Such a
    line moves only when ``held = false`` is given, with a warning of that cost; held by
    default, it is warned of what the held line leaves out (``held = true`` says the choice is
    made). Both name the two consistent choices, a plane of symmetry on every member
    (``symmetric`` with ``roller``) or none, and the members that hang on the line
    (:meth:`assembly.Case.hanging_members`), where refinement converges more slowly."""
    moving = set(case.moving_lines())
    warnings = []
    for jid, joint in case.joints.items():
        ends = case.singular_ends(jid)
        if not ends:
            continue
        names = ", ".join(f"{e.plate}.{e.edge}" for e in ends)
        why = (f"its end edges {names} are a plane of symmetry for part of the motion only "
               "(in-plane roller or bending symmetric, not both on every member)")
        fix = ('condition = "symmetric" with in_plane = "roller" on all of them where the end '
               'is a plane of symmetry of the structure, or in_plane = "diaphragm" or "fixed" '
               "where it is not")
        hanging = case.hanging_members(jid)
        line = "hinge" if joint.kind == "hinge" else "junction line"
        hangs = (f"; {', '.join(hanging)} {'hangs' if len(hanging) == 1 else 'hang'} on it (no "
                 "edge of its own holds it across the line in its plane), so the line's ends "
                 "hold it only at a point, through another member's bending support, and "
                 "refinement converges more slowly") if hanging else ""
        if jid in moving:
            message = (f"{line} {jid} moves but {why}: its line loads are singular at "
                       "its ends, where its members carry logarithmic corner functions and edge "
                       f"waves reaching {SINGULAR_END_REACH:g} times further, at 30 to 50 "
                       "times the cost of the held line, and its field keeps an error that the "
                       "error estimate may understate (on an L fold and a T junction against "
                       "finite elements, up to 1.5e-4 in w and 1e-3 in-plane)"
                       f"{hangs} (docs/method.md section 10.4); set held = true, or {fix}")
        elif joint.held is None and not members_coplanar(joint, case.plates):
            message = (f"{line} {jid} is held in translation by default: {why}, where "
                       f"moving it costs 30 to 50 times more{hangs} "
                       "(docs/method.md section 10.4), and the held line leaves out its "
                       "members' in-plane motion (on an L fold with such ends, 0.1 to 1.7 % of "
                       "w at 300 Hz and 1 kHz; on a three-bay stiffened panel, 2 to 110 %); "
                       "set held = false to move it, held = true to keep it held without this "
                       f"warning, or {fix}")
        else:
            continue
        warnings.append((("joints", jid, "held"), message))
    return warnings


def _in_plane_groups(case: Case, plates: Iterable[str]) -> list[list[str]]:
    """The plates that carry in-plane waves, grouped by what couples their in-plane fields:
    the connected components of the graph of their moving lines and coplanar joints."""
    graph = nx.Graph()
    graph.add_nodes_from(plates)
    moving = set(case.moving_lines())
    for jid, joint in case.joints.items():
        members = [pid for pid in joint.plates if pid in graph]
        if (jid in moving or joint.kind == "coplanar") and members:
            graph.add_edges_from((members[0], other) for other in members[1:])
    return [[pid for pid in case.plates if pid in group]
            for group in nx.connected_components(graph)]


def _floating_issues(case: Case) -> list[tuple[_Loc, str]]:
    """A warning per group of plates coupled in their plane (:func:`_in_plane_groups`) that is
    supported in bending somewhere but held in its plane nowhere: no edge of theirs fixed,
    ``diaphragm`` or ``roller`` in plane (a supported edge with ``in_plane = "free"``, or a
    free one; a hinge or a held line would hold it:
    :func:`solver.in_plane.in_plane_edge_conditions`). Such plates are held in their plane
    only through one another's bending supports, a near-mechanism, and refinement converges
    from far off: the trihedral corner so supported is 2.4e-2 off independent finite elements
    at resolution 1.5 and 1.8e-3 at 3.375 (``docs/method.md`` section 10.4), though its
    estimate follows.
    A structure that nothing supports (``cases/box_with_wall.toml``) is not warned: it floats
    as a whole, held by its inertia, and converges as its corners do."""
    conditions = in_plane_edge_conditions(case)
    supported = {}  # plate: index of its first boundary supported in bending
    for i, bc in enumerate(case.boundaries):
        if bc.condition != "free":
            supported.setdefault(case.edge(bc.edge).plate, i)
    warnings = []
    for group in _in_plane_groups(case, conditions):
        held = any(condition != "free" for pid in group for condition in conditions[pid].values())
        on_supports = [supported[pid] for pid in group if pid in supported]
        if held or not on_supports:
            continue
        names = ", ".join(group)
        warnings.append((("boundaries", min(on_supports), "in_plane"),
                         f"plates {names} float in their plane: no edge of theirs is held in "
                         "plane (their supported edges have in_plane = \"free\"), so they are "
                         "held there only through one another's bending supports, and "
                         "refinement converges from far off (a trihedral corner so supported: "
                         "2.4e-2 off at resolution 1.5, 1.8e-3 at 3.375; "
                         "docs/method.md section 10.4); read the error estimate or solve with "
                         "--tolerance, and give in_plane = \"fixed\", \"diaphragm\" or "
                         "\"roller\" to the edges that are held in their plane"))
    return warnings


def _idle_in_plane_issues(case: Case) -> list[tuple[_Loc, str]]:
    """One warning naming the boundaries whose ``in_plane`` condition does nothing whatever
    the lines' ``held``: their plate carries no in-plane waves
    (:func:`solver.in_plane.in_plane_plates`) and could carry them only as a member of a
    junction between non-coplanar plates, or joined to one by coplanar joints. (On a
    member of a held line the condition is the structure's, ready for ``held = false``.)"""
    could_move = coplanar_closure(case, {
        p for joint in case.joints.values() if joint.kind in ("junction", "hinge")
        and not members_coplanar(joint, case.plates) for p in joint.plates})
    could_move |= set(in_plane_plates(case))
    idle = [(i, bc.edge) for i, bc in enumerate(case.boundaries)
            if bc.in_plane is not None and case.edge(bc.edge).plate not in could_move]
    if not idle:
        return []
    shown = ", ".join(edge for _, edge in idle[:4]) + (", ..." if len(idle) > 4 else "")
    return [(("boundaries", idle[0][0], "in_plane"),
             f"the in-plane condition of {len(idle)} edge(s) ({shown}) does nothing: their "
             "plates carry no in-plane waves and cannot (no member of a junction between "
             "non-coplanar plates, nor joined to one by coplanar joints), so only their "
             "bending is solved; remove in_plane there")]


def _weights_issues(case: Case) -> list[tuple[_Loc, str]]:
    r"""A warning when the scale-free weights (``[updating] r = "auto"``) meet
    ``misfit = "global"``. The weights balance each joint's law against its own plates' data
    weighed by their stated relative noise, :math:`\sigma_p^2\propto\|\tilde u_p\|^2/m_p`
    (``updating.inverse.weights``); the global misfit weighs every value by the whole data's
    norm instead, so a plate far from the load counts far below its noise while its joints'
    laws keep their local weight. On the 8- and 50-bay stiffened panels of
    ``bench/bench_scale.py`` (±10 % noise) two and one wrong welds went to the lower bound,
    their estimates outside their own intervals; with the per-plate misfit every wrong weld of
    4 to 50 bays is found, and no right one (``docs/updating.md`` section 6.6)."""
    settings = case.updating
    if not (settings.automatic and settings.misfit == "global"):
        return []
    return [(("updating", "misfit"),
             'misfit = "global" with the scale-free weights (r = "auto"): those weigh each '
             "plate's data by its own stated noise, which the global misfit does not, so "
             "plates far from the load count below their noise and their joints can go to "
             "the bounds (docs/updating.md section 6.6); drop misfit (per_plate), or give a "
             "number for r (0.8 is the paper's)")]


def description_issues(
    case: Case, frequencies: Iterable[float] | None = None, need_loads: bool = False,
) -> tuple[list[tuple[_Loc, str]], list[tuple[_Loc, str]]]:
    """Physical and numerical sanity of a valid description: ``(errors, warnings)``.

    Checked at the highest frequency (ray counts grow with it), each plate:

    * **ray resolution** -- every ray family must reach :data:`UNDER_RESOLVED` (0.6) of the
      resolution rule (:func:`solver.rays.automatic_ray_counts`, ``docs/method.md`` section 5.2),
      else an error names the per-plate override (``discretisation.plates.P1.interior``) or
      ``discretisation.resolution`` (``measurement.resolution`` for the simulated
      experiment), the frequency, the count given and the count the rule asks; below
      :data:`UNDER_RESOLVED_WARNING` (0.85) a warning;
    * **size** -- more than :data:`MAX_RAYS_PER_PLATE` ray unknowns on one plate is an error
      (the plate spans too many wavelengths for a dense Trefftz solve);
    * **thin-plate theory** -- a bending wavelength below :data:`KIRCHHOFF_WAVELENGTH`
      thicknesses warns;
    * **measurement grid** -- more than :data:`MAX_GRID_POINTS` points on a plate is an
      error (spacing in mm instead of m?);
    * **loads** (if `need_loads`) -- a description without loads has a zero response;
    * **moving lines** -- a junction line whose end is a plane of symmetry for part of the
      motion only warns, moving or held by default (:func:`_singular_end_issues`); so do
      in-plane conditions on plates without in-plane waves (:func:`_idle_in_plane_issues`) and
      plates supported in bending but held in their plane nowhere (:func:`_floating_issues`);
    * **weights** -- the scale-free weights with ``misfit = "global"`` warn
      (:func:`_weights_issues`).

    Parameters
    ----------
    case : assembly.Case
        A validated description.
    frequencies : sequence of float, optional
        Frequencies to check instead of the description's (e.g. ``vtcr solve --frequency``);
        issues about the frequency are then located at ``--frequency``.
    need_loads : bool, optional
        Report a description without ``[[loads]]`` (solving commands).

    Returns
    -------
    errors, warnings : list of (tuple, str)
        ``(location, message)``, the location a field path such as
        ``("discretisation", "plates", "P1", "interior")``.
    """
    errors = _load_issues(case, need_loads) + _grid_issues(case)
    given = frequencies is not None
    frequencies = tuple(frequencies) if given else case.frequencies

    def location(g: float) -> _Loc:
        """Where frequency ``g`` was given: the option, or the description's field."""
        if given:
            return ("--frequency",)
        if case.frequency is not None:
            return ("frequency",)
        return ("frequencies", frequencies.index(g))

    f = max(frequencies)
    f_loc = location(f)
    units = _millimetres_against_pascals(case)
    errors = ([units] if units else []) + errors
    scale_errors, warnings = _scale_issues(case, frequencies, location)
    warnings += (_singular_end_issues(case) + _idle_in_plane_issues(case)
                 + _floating_issues(case) + _weights_issues(case))
    if scale_errors:  # the quantities below would overflow or vanish
        return errors + scale_errors, warnings
    plates = _plate_rays(case, f)
    for rays in plates:  # plate by plate: its overrides' counts, then thin-plate theory
        override_errors, override_warnings = _override_issues(rays)
        errors += override_errors
        warnings += override_warnings + _thin_plate_issues(rays, f, f_loc)
    errors += _size_issues(plates, f, f_loc)
    resolution_errors, resolution_warnings = _resolution_issues(case, plates)
    errors += resolution_errors
    warnings += resolution_warnings
    if case.joints and not errors:
        errors += _memory_issues(case, f, f_loc)
    return errors, warnings


def _memory_issues(case: Case, frequency: float, loc: _Loc) -> list[tuple[_Loc, str]]:
    """An error if the estimated memory of a solve exceeds the memory available now."""
    estimate = estimate_size(case, frequency)
    available = available_memory()
    if available is None or estimate.solve_bytes <= available:
        return []
    return [(loc, f"at {frequency:g} Hz the VTCR problem has {estimate.interface_unknowns} "
             f"interface unknowns and {estimate.ray_unknowns} ray unknowns in "
             f"{estimate.plates} plates; its solve needs about "
             f"{estimate.solve_bytes / 1e9:.2g} GB, "
             f"more than the {available / 1e9:.2g} GB available (vtcr check prints the "
             "estimate); lower the frequency or [discretisation] resolution, or study a part "
             "of the structure")]


def check_description(case: Case, source: str, frequencies: Iterable[float] | None = None,
                      need_loads: bool = False) -> list[str]:
    """Raise the errors of :func:`description_issues`; return its warnings as lines.

    Parameters
    ----------
    case : assembly.Case
    source : str
        The description's file name, for the messages.
    frequencies, need_loads
        As in :func:`description_issues`.

    Returns
    -------
    list of str
        One line per warning, ``source: field.path: message``.

    Raises
    ------
    assembly.DescriptionError
        With every error, one :class:`assembly.errors.Issue` each.
    """
    errors, warnings = description_issues(case, frequencies, need_loads)
    if errors:
        raise DescriptionError(Issue(source, format_path(loc), msg) for loc, msg in errors)
    return [str(Issue(source, format_path(loc), msg)) for loc, msg in warnings]
