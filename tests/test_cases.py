"""The example descriptions in ``cases/``: every file loads and solves, and each of the three
cases of Dorival, Rouch & Allix (2008), section 5, has the physical property it was built for
(see the header comment of each file for how it was built).

Every check below is computed from the VTCR field and compared with physics (power balance,
an exact series solution, the joint law, resonance), never with numbers saved from an earlier
run. Tolerances are stated with their reason next to each assertion.
"""


import numpy as np
import pytest
from exact import EdgeLoad, Section, coplanar, levy_chain
from support import CASES

from assembly import load_case
from solver import field_grid, solve_case
from solver.channels import joint_residuals
from solver.joint_rules import joint_parameters
from solver.substructure import build_assembly_system, solve_assembly

CASE_FILES = sorted(CASES.glob("*.toml"))
PAPER_CASES = ("two_plates", "four_plates", "folded_plate")


def load(name):
    return load_case(CASES / f"{name}.toml")


def gauss(length, n):
    """Gauss-Legendre nodes and weights on [0, length]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * length * (x + 1.0), 0.5 * length * w


def rms_response(case, frequency, spacing=0.02):
    """Spatial RMS of |w| (m) over a fine grid of every plate: the resonance indicator."""
    solution = solve_case(case, frequency=frequency)
    values = np.concatenate([solution.w(pid, field_grid(case, pid, spacing))
                             for pid in case.plates])
    return float(np.sqrt(np.mean(np.abs(values) ** 2)))


def on_measurement_grid(case, solution):
    """w at the description's measurement points, in their order."""
    points = case.measurement_points()
    return np.concatenate([
        solution.w(pid, np.array([(x, y) for p, x, y in points if p == pid]))
        for pid in case.plates if any(p == pid for p, _, _ in points)
    ])


def rigidity(case, pid):
    """Complex rigidity D* = E h^3 (1 + j eta) / (12 (1 - nu^2)) of a plate, and nu."""
    material, plate = case.material_of(pid), case.plates[pid]
    return (material.flexural_rigidity(plate.thickness) * (1 + 1j * material.loss_factor),
            material.poisson_ratio)


# ----------------------------------------------------------------------------------------------
# every description
# ----------------------------------------------------------------------------------------------

def test_the_paper_cases_are_present():
    assert {p.stem for p in CASE_FILES} >= set(PAPER_CASES)


# the 10 x 10 grid takes 35 s and 2 GB: out of the default run; a 6 x 6 grid is solved against
# the Navier series in tests/test_interface.py, and the file is its generator's output
# (tests/test_large_cases.py)
SLOW_CASES = ("grid_10x10",)


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow)
                                  if p.stem in SLOW_CASES else p for p in CASE_FILES],
                         ids=lambda p: p.stem)
def test_case_loads_and_solves(path):
    """Smoke test: each description validates and solves at its first frequency, with a
    finite, non-zero field on its measurement grid, no conditioning warning, and (assemblies)
    joint residuals at the discretisation floor of the model's own parameters."""
    case = load_case(path)
    solution = solve_case(case)
    w = on_measurement_grid(case, solution)
    assert w.size == len(case.measurement_points()) > 0
    assert np.all(np.isfinite(w)) and np.max(np.abs(w)) > 0
    assert solution.warnings == ()
    for joint, residual in getattr(solution, "residuals", {}).items():
        # 1e-4: the paper's floor is 1e-3 to 1e-2 with 100 dof per plate; ours is far lower
        assert 0 <= residual < 1e-4, (joint, residual)


# ----------------------------------------------------------------------------------------------
# section 5.1: two plates, damped joint, edge shear, 155 Hz resonance
# ----------------------------------------------------------------------------------------------

def test_two_plates_power_balance():
    """Power injected by the edge shear = plate dissipation (eta) + joint dissipation.

    P_in = 1/2 Re int conj(p) j omega w ds on P1.left; P_plates = 1/2 omega eta D a(w, w*)
    (Gauss 60 x 60 per plate); P_joint = 1/2 omega k zeta int |theta_A + theta_B|^2 ds with
    theta = dw/dn (outward normals: +w_x on P1.right, -w_x on P2.left). Tolerance 1e-5: the
    joint term is about 2 % of the input, so a missing or mis-scaled joint dissipation (or a
    sign error on a slope) fails by three orders of magnitude, while the balance of the VTCR
    field holds to about 1e-9 and the quadratures are converged to 1e-14.
    """
    case = load("two_plates")
    solution = solve_case(case)
    omega = 2 * np.pi * case.frequencies[0]
    (lx, ly), joint = case.plates["P1"].size, case.joints["G1"]
    assert case.plates["P2"].size == (lx, ly)
    p = case.loads[0].amplitude
    y, wy = gauss(ly, 80)
    w_left = solution.plates["P1"].field(np.c_[np.zeros_like(y), y])["w"]
    injected = 0.5 * np.real(np.sum(wy * np.conj(p) * 1j * omega * w_left))
    theta_a = solution.plates["P1"].field(np.c_[np.full_like(y, lx), y], ("w_x",))["w_x"]
    theta_b = -solution.plates["P2"].field(np.c_[np.zeros_like(y), y], ("w_x",))["w_x"]
    in_joint = 0.5 * omega * joint.stiffness * joint.loss_factor * float(
        np.sum(wy * np.abs(theta_a + theta_b) ** 2))
    in_plates = 0.0
    for pid in ("P1", "P2"):
        D, nu = rigidity(case, pid)
        (gx, wx), (gy, wgy) = gauss(lx, 60), gauss(ly, 60)
        X, Y = np.meshgrid(gx, gy, indexing="ij")
        f = solution.plates[pid].field(np.c_[X.ravel(), Y.ravel()], ("w_xx", "w_xy", "w_yy"))
        density = ((1 - nu) * (abs(f["w_xx"]) ** 2 + 2 * abs(f["w_xy"]) ** 2
                               + abs(f["w_yy"]) ** 2) + nu * abs(f["w_xx"] + f["w_yy"]) ** 2)
        in_plates += 0.5 * omega * D.imag * float(np.outer(wx, wgy).ravel() @ density)
    assert injected > 0
    assert in_joint > 0.01 * injected  # the joint term matters (about 2 % here)
    assert abs(injected - in_plates - in_joint) <= 1e-5 * injected


def test_two_plates_155_hz_is_a_resonance_and_matches_the_exact_levy_chain():
    """155 Hz is a local maximum of the response, and the field is the exact one there.

    Measured: RMS |w| at 155 Hz is 1.9 x that at 150 Hz and 3.4 x that at 160 Hz; the factor
    1.3 leaves room for discretisation changes while still failing if the peak moved by more
    than about 2 Hz (measured half-power bandwidth 2.2 Hz, plate and joint damping). The
    simply supported top/bottom edges make the case a Levy chain, so the VTCR field is checked
    against the exact series (tests/exact.py): 7.7e-4 measured, 1e-2 allowed (the
    accuracy target of the solver's own chain tests).
    """
    case = load("two_plates")
    peak = rms_response(case, 155.0)
    assert peak > 1.3 * rms_response(case, 150.0)
    assert peak > 1.3 * rms_response(case, 160.0)

    lx, ly = case.plates["P1"].size
    D, nu = rigidity(case, "P1")
    material = case.material_of("P1")
    joint, shear = case.joints["G1"], case.loads[0]
    reference = levy_chain(
        [Section(lx, D, nu, material.density * case.plates["P1"].thickness)] * 2, ly,
        2 * np.pi * 155.0, joints=[coplanar(joint.stiffness, joint.loss_factor, joint.mass)],
        left="free", right="clamped",
        edge_loads=[EdgeLoad("left", "edge_shear", shear.amplitude, shear.distribution)],
        n_terms=400)
    solution = solve_case(case)
    num = den = 0.0
    for i, pid in enumerate(("P1", "P2")):
        points = field_grid(case, pid, 0.04)
        exact = reference.w(points[:, 0], points[:, 1], plate=i)
        num += np.linalg.norm(solution.w(pid, points) - exact) ** 2
        den += np.linalg.norm(exact) ** 2
    assert np.sqrt(num / den) < 1e-2


# ----------------------------------------------------------------------------------------------
# section 5.2: four plates, four joints, localisation
# ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("index", [0, 1, 2])
def test_four_plates_true_structure_is_at_resonances(index):
    """The TRUE structure (Table 3 joints) peaks at each case frequency: RMS |w| measured
    2.78 / 1.65 (218 Hz), 2.47 / 1.46 (248 Hz), 1.73 / 1.95 (309.4 Hz) times the values 3 Hz
    below / above (half-power bandwidth eta f = 2.2-3.1 Hz); 1.3 fails if a peak moves by more
    than about 1 Hz."""
    true = load("four_plates").true_case()
    f = true.frequencies[index]
    peak = rms_response(true, f, spacing=0.025)
    assert peak > 1.3 * rms_response(true, f - 3.0, spacing=0.025)
    assert peak > 1.3 * rms_response(true, f + 3.0, spacing=0.025)


def test_four_plates_residuals_localise_the_wrong_joints():
    """At the true parameters the true case's joint residuals are at the discretisation floor,
    while the model case (all log k = 2), solved and then evaluated with the true joint laws,
    is far from it on the three wrong joints and stays at the floor on G3 (true = model).

    At the first frequency (218 Hz). Floor bound 1e-4 (measured: at most 7e-8, on the stiff
    G2); "far" means > 1e-3, ten times that bound (measured: G1 0.25, G2 0.52, G4 2.2e-3). The
    response is also sensitive to the joints: the model and true fields differ by 63 % (relative
    L2 on the measurement grid); more than 20 % is required, twice the 10 % measurement noise.
    """
    model = load("four_plates")
    true = model.true_case()
    f = model.frequencies[0]
    true_solution = solve_case(true)
    for joint, residual in true_solution.residuals.items():
        assert residual < 1e-4, (joint, residual)

    system = build_assembly_system(model, f)
    model_solution = solve_assembly(model, f, system=system)
    at_truth = joint_residuals(system.channels, joint_parameters(true, system.omega),
                               model_solution.interface, model_solution.reference.total)
    for joint in ("G1", "G2", "G4"):
        assert at_truth[joint] > 1e-3, (joint, at_truth)
    assert at_truth["G3"] < 1e-4, at_truth

    w_true = on_measurement_grid(true, true_solution)
    w_model = on_measurement_grid(model, model_solution)
    assert np.linalg.norm(w_model - w_true) > 0.2 * np.linalg.norm(w_true)


# ----------------------------------------------------------------------------------------------
# section 5.3: folded plate, hinge on needles
# ----------------------------------------------------------------------------------------------

def test_folded_plate_hinge_law_on_the_fold():
    """On the fold (P1.right = P2.left) of the true structure (log k = 2.4):

    * w = 0 on both faces (the needles): max |w| on the fold < 2e-4 max |w| of the faces
      (measured 5.1e-5 and 1.3e-5 since the corner functions where the fold meets the free
      edges, ``docs/method.md`` section 5.5; 7.8e-4 and 8.6e-4 with the rays alone, 5e-3 at
      the default resolution, which is why the case uses resolution 1.25);
    * M_n^A = M_n^B = k (theta_A + theta_B), with M_n = -D*(w_xx + nu w_yy) and
      theta = dw/dn (+w_x on P1.right, -w_x on P2.left), relative L2 along the fold (Gauss),
      at resolution 1.5: M_n^A = M_n^B measured 4.6e-3, M_n = k Theta 4.5e-3 and 1.1e-3
      (1.2 %, 3.1 % and 3.4 % with the rays alone); bounds 1.5e-2. The law holds on the
      fold's load functions only, and near the fold's ends the moment goes like
      t^(0.069 +- 0.439j): the traces converge slowly (M_n = k Theta on P1 6.4 %, 2.7 %,
      0.45 %, 0.67 % at resolutions 1.0, 1.25, 1.5, 2.0). 1.5e-2 still fails for a wrong sign
      of a slope, a hinge that translates, or k off by more than about 0.007 in log10 k.
    """
    case = load("folded_plate").true_case()
    solution = solve_case(case)
    traces = solve_case(case, resolution=1.5)
    joint = case.joints["G1"]
    assert joint.kind == "hinge" and joint.log10_stiffness == 2.4
    lx, ly = case.plates["P1"].size
    quantities = ("w", "w_x", "w_y", "w_xx", "w_xy", "w_yy")
    y, wy = gauss(ly, 80)
    a = solution.plates["P1"].field(np.c_[np.full_like(y, lx), y], quantities)
    b = solution.plates["P2"].field(np.c_[np.zeros_like(y), y], quantities)
    w_max = max(np.abs(solution.w(pid, field_grid(case, pid, 0.005))).max()
                for pid in case.plates)
    assert np.abs(a["w"]).max() < 2e-4 * w_max
    assert np.abs(b["w"]).max() < 2e-4 * w_max

    a = traces.plates["P1"].field(np.c_[np.full_like(y, lx), y], quantities)
    b = traces.plates["P2"].field(np.c_[np.zeros_like(y), y], quantities)
    D, nu = rigidity(case, "P1")
    moment_a = -D * (a["w_xx"] + nu * a["w_yy"])
    moment_b = -D * (b["w_xx"] + nu * b["w_yy"])
    spring = joint.complex_stiffness * (a["w_x"] - b["w_x"])

    def norm(values):
        return np.sqrt(np.sum(wy * np.abs(values) ** 2))

    assert norm(moment_a - moment_b) < 1.5e-2 * norm(moment_a)
    assert norm(moment_a - spring) < 1.5e-2 * norm(moment_a)
    assert norm(moment_b - spring) < 1.5e-2 * norm(moment_b)
