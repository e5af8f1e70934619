"""Kinematics, constitutive outputs and node loads of the connector FMUs,
checked through fmpy against the independent numpy reference in _ref.py.

Protocol (docs/fmi.md, direct feedthrough): instantiate, setupExperiment,
enterInitializationMode, set parameters and the initial pose,
exitInitializationMode (this fixes x0, alpha10, ...), then set new inputs and
read the outputs, usually without stepping.  Where a test steps, the node
velocities are zero unless the test is about the extrapolation.

Tolerances (all stated where used):
  * TOL_KIN: positions and angles.  Values are O(1) (|d| <= ~2.5 m, angles
    <= 2.5 rad) and come out of a few dozen flops, so double round-off is
    ~1e-15; 5e-12 (~1e-12 relative to the magnitude scale) leaves a factor of
    ~1000 for a different but exact formulation (acos vs atan2, other
    product order) and still catches any formula error.
  * TOL_RATE: relative velocities against the reference, whose gradients
    are fourth-order central differences (h = 5e-4): error ~1e-12 relative
    (truncation h^4 c^(5)/30, round-off 1.5 eps c/h; measured agreement with
    the current FMU <= 4e-12), rates are O(5) here, so 1e-10 absolute.
  * TOL_LOAD_REL: loads against the reference's virtual-work loads (same
    gradients): 1e-10 of the load scale.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import _ref
from conftest import Connector

TOL_KIN = 5e-12
TOL_RATE = 1e-10
TOL_LOAD_REL = 1e-10

ALL = list(_ref.VARIANTS)
CENTRED = ["ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing"]
WITH_TORSION = ["ProjectionFlexionTorsion", "Bushing"]
LOAD_NAMES = ["a.f", "a.m", "b.f", "b.m"]


# ==========================================================================
# 1. self-checks of the reference (hand examples; they run without FMUs)
# ==========================================================================


def _close(a, b, tol=1e-14):
    return np.allclose(a, b, rtol=0.0, atol=tol)


def test_ref_quaternion_conventions():
    # 90 deg about z maps local x to world y
    q = np.array([math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)])
    R = _ref.quat_to_matrix(q)
    assert _close(R[:, 0], [0, 1, 0]) and _close(R[:, 1], [-1, 0, 0])
    rng = np.random.default_rng(1)
    for _ in range(20):
        R = _ref.random_rotation(rng, 3.0)
        assert _close(_ref.quat_to_matrix(_ref.matrix_to_quat(R)), R)
        phi = rng.normal(size=3)
        assert _close(_ref.quat_to_matrix(_ref.quat_exp(phi)), _ref.rotvec_to_matrix(phi))
        # world-frame composition: R(exp(phi) q) = R(phi) R(q)
        qq = _ref.matrix_to_quat(R)
        assert _close(_ref.quat_to_matrix(_ref.quat_mul(_ref.quat_exp(phi), qq)), _ref.rotvec_to_matrix(phi) @ R)


def test_ref_pure_torsion_is_geodesic_midpoint():
    th = 0.7
    E, a1, a2, beta = _ref.centred_triad(np.eye(3), _ref.rot_z(th))
    assert abs(beta - th) < 1e-15 and abs(a1) < 1e-15 and abs(a2) < 1e-15
    assert _close(E, _ref.rot_z(th / 2))


def test_ref_pure_flexion():
    th = 0.9
    # about x: q = +e1, triad = frame a rotated by th/2 about x
    E, a1, a2, beta = _ref.centred_triad(np.eye(3), _ref.rot_x(th))
    assert abs(a1 - th) < 1e-15 and abs(a2) < 1e-15 and abs(beta) < 1e-15
    assert _close(E, _ref.rot_x(th / 2))
    # about y: alpha2
    E, a1, a2, beta = _ref.centred_triad(np.eye(3), _ref.rot_y(th))
    assert abs(a1) < 1e-15 and abs(a2 - th) < 1e-15 and abs(beta) < 1e-15


def test_ref_three_two_three_closed_form():
    # Rb = Rz(phi) Ry(alpha) Rz(beta - phi) relative to a: then q = Rz(phi) e2
    # (in a's frame), the torsion is beta and, working the construction of
    # docs/physics.md, Kinematics by hand, alpha1 = alpha sin(beta/2 - phi),
    # alpha2 = alpha cos(beta/2 - phi).
    rng = np.random.default_rng(2)
    for _ in range(50):
        Ra = _ref.random_rotation(rng, 3.0)
        phi, al, be = rng.uniform(-3, 3), rng.uniform(0, 2.8), rng.uniform(-3, 3)
        Rb = Ra @ _ref.rot_z(phi) @ _ref.rot_y(al) @ _ref.rot_z(be - phi)
        E, a1, a2, beta = _ref.centred_triad(Ra, Rb, be)
        assert abs(beta - be) < 1e-12
        assert abs(a1 - al * math.sin(be / 2 - phi)) < 1e-12
        assert abs(a2 - al * math.cos(be / 2 - phi)) < 1e-12
        # properties docs/physics.md, Kinematics lists
        assert abs(a1**2 + a2**2 - _ref.flexion_angle(Ra, Rb) ** 2) < 1e-11
        assert _close(E.T @ E, np.eye(3), 1e-14) and abs(np.linalg.det(E) - 1) < 1e-14
        bis = (Ra[:, 2] + Rb[:, 2]) / np.linalg.norm(Ra[:, 2] + Rb[:, 2])
        assert _close(E[:, 2], bis, 1e-13)
        q = np.cross(Ra[:, 2], Rb[:, 2])
        assert abs(E[:, 2] @ q) < 1e-14
        # swap a <-> b: same triad, angles negated
        E2, b1, b2, beta2 = _ref.centred_triad(Rb, Ra, -be)
        assert _close(E2, E, 1e-12)
        assert abs(b1 + a1) < 1e-12 and abs(b2 + a2) < 1e-12 and abs(beta2 + beta) < 1e-12


def test_ref_torsion_branch():
    assert abs(_ref.centred_triad(np.eye(3), _ref.rot_z(3.0), 0.0)[3] - 3.0) < 1e-14
    assert abs(_ref.centred_triad(np.eye(3), _ref.rot_z(-3.0), 3.0)[3] - (2 * math.pi - 3.0)) < 1e-14
    # a full turn: frames coincide, but the triad is turned by pi (beta/2)
    E, _, _, beta = _ref.centred_triad(np.eye(3), _ref.rot_z(2 * math.pi), 2 * math.pi - 0.1)
    assert abs(beta - 2 * math.pi) < 1e-14
    assert _close(E, _ref.rot_z(math.pi), 1e-14)


def test_ref_radial_thrust():
    r, l, e_r = _ref.radial_thrust([3.0, 4.0, 5.0], np.eye(3))
    assert (r, l) == (5.0, 5.0) and _close(e_r, [0.6, 0.8, 0.0])
    Ra = _ref.rot_x(math.pi / 2)  # e3a = -y_world... (0, -1, 0)
    r, l, e_r = _ref.radial_thrust([0.0, -2.0, 1.0], Ra)
    assert abs(l - 2.0) < 1e-15 and abs(r - 1.0) < 1e-15 and _close(e_r, [0, 0, 1])


def test_ref_planar():
    th = 1.1
    p = _ref.planar([1.0, 2.0, 3.0], np.eye(3), _ref.rot_x(th))
    assert _close([p["x"], p["y"], p["z"], p["alpha"], p["phi2"], p["phi3"]], [1, 2, 3, th, 0, 0])
    # pi branch by continuity: rotation 2.5 about e1 seen from prev 2.4
    assert abs(_ref.planar([0, 0, 0], np.eye(3), _ref.rot_x(2.5), 2.4)["alpha"] - 2.5) < 1e-14
    # misalignment: small rotation of b about e2 -> phi2, about e3 -> phi3
    e = 0.01
    p = _ref.planar([0, 0, 0], np.eye(3), _ref.rot_y(e))
    assert abs(p["phi2"] - math.sin(e)) < 1e-15 and abs(p["phi3"]) < 1e-15
    p = _ref.planar([0, 0, 0], np.eye(3), _ref.rot_z(e))
    assert abs(p["phi3"] - math.sin(e)) < 1e-15 and abs(p["phi2"]) < 1e-15


def test_ref_gradients_and_loads():
    # stretched Cartesian spring at identity frames: grad x wrt b.r = e1,
    # loads pull a towards b
    pose = {"a.r": np.zeros(3), "a.q": [1, 0, 0, 0], "b.r": np.array([1.0, 0, 0]), "b.q": [1, 0, 0, 0]}
    G = _ref.gradients("ProjectionCartesian", pose)
    assert _close(G["CP1"][6:9], [1, 0, 0], 1e-9) and _close(G["CP1"][0:3], [-1, 0, 0], 1e-9)
    loads = _ref.node_loads(G, {"CP1": 10.0})
    assert _close(loads["a.f"], [10, 0, 0], 1e-8) and _close(loads["b.f"], [-10, 0, 0], 1e-8)
    # the reference's virtual-work loads are in equilibrium (objectivity)
    rng = np.random.default_rng(3)
    for v in ALL:
        init = _ref.random_pose(rng, v)
        pose = _ref.random_pose(rng, v)
        out = _ref.connector(v, pose, init, _spring_params(v, rng, damping=True))
        _assert_equilibrium(v, pose, out, 1e-10)


def test_ref_connector_energy_is_potential():
    # elastic loads of the reference equal -dE/d(motion)
    rng = np.random.default_rng(4)
    for v in ALL:
        init = _ref.random_pose(rng, v, with_velocity=False)
        pose = _ref.random_pose(rng, v, with_velocity=False)
        params = _spring_params(v, rng, damping=False)
        out = _ref.connector(v, pose, init, params)
        h = 1e-5
        for m, (node, kind, j) in enumerate(_ref.MOTIONS):
            Ep = _ref.connector(v, _ref.perturb(pose, node, kind, j, h), init, params)["energy.stored"]
            Em = _ref.connector(v, _ref.perturb(pose, node, kind, j, -h), init, params)["energy.stored"]
            load = out[f"{node}.{'f' if kind == 'r' else 'm'}"][j]
            assert abs(-(Ep - Em) / (2 * h) - load) < 1e-6 * max(1.0, _load_scale(out))


# ==========================================================================
# FMU driver: conftest's Connector (scripts/cosim/driver.py)
# ==========================================================================


def set_pose(c, pose):
    c.set(_ref.pose_to_inputs(c.variant, pose))


def node_loads(c):
    return {n: c.vec(n) for n in _ref.VARIANTS[c.variant]["loads"]}


@pytest.fixture
def connect(make_slave):
    """connect(variant, pose=None, params=None) -> Connector, started at pose
    when given (conftest's make_slave frees the instances; FMU log messages
    are printed, so pytest shows them for a failing test)."""
    count = [0]

    def make(variant, pose=None, params=None):
        count[0] += 1
        c = Connector(variant, make_slave(variant, instance_name=f"{variant}-{count[0]}"))
        if pose is not None:
            c.start(params or {}, _ref.pose_to_inputs(variant, pose))
        return c

    return make


# ==========================================================================
# helpers
# ==========================================================================

IDENTITY_POSE = {
    "a.r": np.zeros(3),
    "a.q": np.array([1.0, 0, 0, 0]),
    "b.r": np.array([0.5, 0.2, 0.8]),
    "b.q": np.array([1.0, 0, 0, 0]),
}


def _spring_params(variant, rng, damping=True, given=False):
    """Random stiffnesses (translational ~1e3 N/m, rotational ~50 N.m/rad),
    damping (~10 N.s/m, ~0.5 N.m.s/rad) and, for Planar, the penalties."""
    p = {}
    for _name, k in _ref.components_of(variant):
        rot = k > 3
        p[f"elasticity.k{k}"] = float(rng.uniform(20.0, 100.0) if rot else rng.uniform(500.0, 2000.0))
        p[f"damping.c{k}"] = float(rng.uniform(0.2, 1.0) if rot else rng.uniform(5.0, 20.0)) if damping else 0.0
        p[f"reference.given{k}"] = bool(given)
        p[f"reference.value{k}"] = float(rng.uniform(-0.5, 0.5))
    if variant == "Planar":
        p["constraint.stiffness"] = 1.0e5
        p["constraint.damping"] = 50.0 if damping else 0.0
        p["constraint.rotStiffness"] = 1.0e4
        p["constraint.rotDamping"] = 0.0
    return p


def _load_scale(out):
    return max(float(np.linalg.norm(out[n])) for n in LOAD_NAMES if n in out)


def _d(pose):
    return np.asarray(pose["b.r"], float) - np.asarray(pose["a.r"], float)


def _assert_equilibrium(variant, pose, loads, rel):
    """f_a + f_b = 0 and m_a + m_b + d x f_b = 0 (missing loads are zero)."""
    z = np.zeros(3)
    fa, fb = loads.get("a.f", z), loads.get("b.f", z)
    ma, mb = loads.get("a.m", z), loads.get("b.m", z)
    d = _d(pose) if "a.r" in pose else z
    scale = max(
        np.linalg.norm(fa), np.linalg.norm(fb), np.linalg.norm(ma), np.linalg.norm(mb), np.linalg.norm(np.cross(d, fb))
    )
    assert np.linalg.norm(fa + fb) <= rel * scale, (fa, fb)
    assert np.linalg.norm(ma + mb + np.cross(d, fb)) <= rel * scale, (ma, mb, fb)


def _positions_names(variant):
    return [n for n, _k in _ref.components_of(variant)]


def _swap(pose):
    return {
        "a.r": pose["b.r"],
        "a.q": pose["b.q"],
        "b.r": pose["a.r"],
        "b.q": pose["a.q"],
    }


# ==========================================================================
# 2. positions CP/CPR and motions CU/CUR for random poses (+ CV)
# ==========================================================================


@pytest.mark.parametrize("variant", ALL)
def test_positions_and_motions_random_poses(connect, variant):
    rng = np.random.default_rng(100 + ALL.index(variant))
    init = _ref.random_pose(rng, variant)
    c = connect(variant, init)
    names = _positions_names(variant)
    P0 = _ref.positions(variant, init)
    prev = {k: P0[k] for k in ("CPR1", "CPR3") if k in P0}
    # right after initialization: CP = initial position, CU = 0
    got = c.named(names + [_ref.force_names(n)["CU"] for n in names])
    for n in names:
        assert abs(got[n] - P0[n]) <= TOL_KIN, (n, got[n], P0[n])
        assert abs(got[_ref.force_names(n)["CU"]]) <= TOL_KIN
    for i in range(50):
        pose = _ref.random_pose(rng, variant)
        set_pose(c, pose)
        P = _ref.positions(variant, pose, prev)
        V = _ref.velocities(variant, pose, prev)
        outs = names + [_ref.force_names(n)[key] for n in names for key in ("CU", "CV")]
        got = c.named(outs)
        for n in names:
            fn = _ref.force_names(n)
            assert abs(got[n] - P[n]) <= TOL_KIN, (i, n, got[n], P[n])
            # CU = CP - CP(initial), measured along the initial triad (seed 634/637)
            assert abs(got[fn["CU"]] - (P[n] - P0[n])) <= TOL_KIN, (i, fn["CU"])
            assert abs(got[fn["CV"]] - V[n]) <= TOL_RATE, (i, fn["CV"], got[fn["CV"]], V[n])


# ==========================================================================
# 3. alpha1^2 + alpha2^2 = alpha^2
# ==========================================================================


@pytest.mark.parametrize("variant", WITH_TORSION)
def test_flexion_components_make_total_flexion(connect, variant):
    rng = np.random.default_rng(200 + ALL.index(variant))
    c = connect(variant, IDENTITY_POSE)
    for _ in range(50):
        pose = _ref.random_pose(rng, variant)
        set_pose(c, pose)
        got = c.named(["CPR1", "CPR2"])
        Ra, Rb = _ref.quat_to_matrix(pose["a.q"]), _ref.quat_to_matrix(pose["b.q"])
        # alpha = acos(e3a . e3b) (the manual), evaluated as
        # atan2(|e3a x e3b|, e3a . e3b): the same angle, without acos's
        # sqrt(eps) loss of accuracy near alpha = 0
        e3a, e3b = Ra[:, 2], Rb[:, 2]
        alpha = math.atan2(np.linalg.norm(np.cross(e3a, e3b)), e3a @ e3b)
        assert abs(alpha - _ref.flexion_angle(Ra, Rb)) < 1e-6
        assert abs(math.hypot(got["CPR1"], got["CPR2"]) - alpha) <= TOL_KIN


# ==========================================================================
# 4. a <-> b swap symmetry
# ==========================================================================


@pytest.mark.parametrize("variant", CENTRED)
def test_swap_symmetry(connect, variant):
    rng = np.random.default_rng(300 + ALL.index(variant))
    c1 = connect(variant, IDENTITY_POSE)
    c2 = connect(variant, IDENTITY_POSE)
    names = _positions_names(variant)
    for _ in range(30):
        pose = _ref.random_pose(rng, variant, with_velocity=False)
        set_pose(c1, pose)
        set_pose(c2, _swap(pose))
        g1, g2 = c1.named(names), c2.named(names)
        for n in names:
            # same triad, d -> -d: x, y, z -> -x, -y, -z; (a1, a2, beta) -> -(...)
            assert abs(g1[n] + g2[n]) <= TOL_KIN, (n, g1[n], g2[n])


# ==========================================================================
# 5. rigid motion of both nodes
# ==========================================================================


@pytest.mark.parametrize("variant", ALL)
def test_rigid_motion_is_invisible(connect, variant):
    """Both nodes moved by one rigid motion (and given the rigid velocity
    field): CU = 0, CV = 0, CP unchanged, and the node loads are those of the
    initial pose rotated with the motion -- zero for all variants but Planar
    (whose penalty acts on the initial misalignment of e1b)."""
    rng = np.random.default_rng(400 + ALL.index(variant))
    init = _ref.random_pose(rng, variant, with_velocity=False)
    params = _spring_params(variant, rng, damping=True)
    c = connect(variant, init, params)
    names = _positions_names(variant)
    P0 = c.named(names)
    L0 = node_loads(c)
    if variant != "Planar":
        for n, v in L0.items():
            assert np.linalg.norm(v) == 0.0 or np.linalg.norm(v) < 1e-9, (n, v)
    for _ in range(20):
        Q = _ref.random_rotation(rng, math.pi)
        t = rng.uniform(-2, 2, size=3)
        omega, v0 = rng.uniform(-1, 1, size=3), rng.uniform(-1, 1, size=3)
        pose = _ref.rigid_motion(init, Q, t, omega, v0)
        set_pose(c, pose)
        got = c.named(names + [_ref.force_names(n)[k] for n in names for k in ("CU", "CV")])
        for n in names:
            fn = _ref.force_names(n)
            assert abs(got[n] - P0[n]) <= TOL_KIN
            assert abs(got[fn["CU"]]) <= TOL_KIN
            # CV = 0 in exact arithmetic; rigid velocities here are O(5), so
            # round-off is ~1e-15; 1e-9 also admits an FMU that differentiates
            # numerically, and still catches a non-objective rate (O(1))
            assert abs(got[fn["CV"]]) <= 1e-9
        L = node_loads(c)
        # Exact answer: Q L0 (0 but for Planar).  Round-off: stiffness (<= 1e5)
        # times ~1e-15 position errors, or ~1e-15 of the Planar penalty loads;
        # 1e-9 of max(1 N, |L0|) is far above both.
        scale = max(1.0, max(np.linalg.norm(v) for v in L0.values()))
        for n, v in L.items():
            assert np.linalg.norm(v - Q @ L0[n]) <= 1e-9 * scale, (n, v, Q @ L0[n])


# ==========================================================================
# 6. torsion swept through 4 pi
# ==========================================================================


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("variant", WITH_TORSION + ["Planar"])
def test_torsion_sweep_4pi_is_continuous(connect, variant, sign):
    """b turned about the shaft axis (e3 for the projection types, e1 for
    Planar) in 400 steps through +-4 pi, one fmi2DoStep per angle (zero
    velocities, so a step does not move the nodes): the torsion output tracks
    the applied angle on its continuous branch.  A fixed flexion of 0.4 rad
    (projection types) or misalignment-free rotation (Planar) is present, and
    for Bushing a fixed d checks that the triad turns by beta/2 (after 2 pi
    the triad is turned by pi: x, y change sign)."""
    rng = np.random.default_rng(500)
    Ra = _ref.random_rotation(rng, 1.0)
    xa = np.array([0.1, -0.2, 0.3])
    d = np.array([0.4, 0.7, -0.5])

    def pose_at(th):
        if variant == "Planar":
            Rb = Ra @ _ref.rot_x(th)
        else:
            Rb = Ra @ _ref.rot_y(0.4) @ _ref.rot_z(th)
        return {"a.r": xa, "a.q": _ref.matrix_to_quat(Ra), "b.r": xa + d, "b.q": _ref.matrix_to_quat(Rb)}

    c = connect(variant, pose_at(0.0))
    names = _positions_names(variant)
    key = "CPR1" if variant == "Planar" else "CPR3"
    prev = {key: 0.0}
    n_steps = 400
    for i in range(1, n_steps + 1):
        th = sign * 4 * math.pi * i / n_steps
        pose = pose_at(th)
        set_pose(c, pose)
        c.step(1e-3)
        got = c.named(names)
        # the applied angle itself (not only the reference) -- scale 4 pi
        assert abs(got[key] - th) <= TOL_KIN * 4 * math.pi, (i, got[key], th)
        ref = _ref.positions(variant, pose, prev)
        for n in names:
            assert abs(got[n] - ref[n]) <= TOL_KIN * 4 * math.pi, (i, n, got[n], ref[n])
        prev = {key: ref[key]}
        # CU of the torsion = applied angle (initial torsion 0)
        cu = c.named([_ref.force_names(key)["CU"]])[_ref.force_names(key)["CU"]]
        assert abs(cu - th) <= TOL_KIN * 4 * math.pi


@pytest.mark.parametrize("variant", WITH_TORSION)
def test_torsion_principal_value_after_a_jump(connect, variant):
    """docs/physics.md, Kinematics: beta = atan2(...) with the 2 pi branch nearest the previous
    value; from 0, a torsion of 2.5 rad (one jump) is 2.5, not 2.5 - pi."""
    c = connect(variant, IDENTITY_POSE)
    for th in (2.5, -2.5, 1.7):
        pose = dict(IDENTITY_POSE, **{"b.q": _ref.matrix_to_quat(_ref.rot_z(th))})
        set_pose(c, pose)
        got = c.named(["CPR1", "CPR2", "CPR3"])
        assert abs(got["CPR3"] - th) <= TOL_KIN, (th, got)
        assert abs(got["CPR1"]) <= TOL_KIN and abs(got["CPR2"]) <= TOL_KIN
        set_pose(c, IDENTITY_POSE)
        c.step(1e-3)


# ==========================================================================
# 7. node-load equilibrium
# ==========================================================================


@pytest.mark.parametrize("variant", ALL)
def test_node_load_equilibrium(connect, variant):
    """f_a + f_b = 0, m_a + m_b + d x f_b = 0 for random poses, all springs,
    dampers (and Planar penalties) on.  Exact in exact arithmetic; round-off
    is a few eps of the load scale (measured <= 5e-16), tested at 1e-12."""
    rng = np.random.default_rng(600 + ALL.index(variant))
    init = _ref.random_pose(rng, variant)
    c = connect(variant, init, _spring_params(variant, rng, damping=True))
    for _ in range(50):
        pose = _ref.random_pose(rng, variant)
        set_pose(c, pose)
        L = node_loads(c)
        assert _load_scale(L) > 1.0  # the springs are loaded
        _assert_equilibrium(variant, pose, L, 1e-12)


# ==========================================================================
# 8. springs, references, dampers, totals, loads and energy vs the reference
# ==========================================================================


@pytest.mark.parametrize("given", [False, True])
@pytest.mark.parametrize("variant", ALL)
def test_constitutive_outputs_match_reference(connect, variant, given):
    """CEF = k u_mat (u_mat = CP - reference; reference = initial position, or
    reference.value<k> when reference.given<k>), CVF = c CV, CTF = CEF + CVF
    (+ CRF, CSF, zero here: no stops, no friction), Planar penalty reactions,
    energy.stored = sum k u_mat^2 / 2 (+ penalty energy) and node loads by
    virtual work."""
    rng = np.random.default_rng(700 + 10 * ALL.index(variant) + int(given))
    params = _spring_params(variant, rng, damping=True, given=given)
    init = _ref.random_pose(rng, variant)
    c = connect(variant, init, params)
    names = _positions_names(variant)
    out_names = list(names)
    for n in names:
        out_names += list(_ref.force_names(n).values())
    if variant == "Planar":
        out_names += ["CRF1", "CTF1", "CRM2", "CTM2", "CRM3", "CTM3"]
    out_names += ["energy.stored"]
    out_names = list(dict.fromkeys(out_names))
    for i in range(20):
        pose = _ref.random_pose(rng, variant)
        set_pose(c, pose)
        ref = _ref.connector(variant, pose, init, params)
        got = c.named(out_names)
        # internal consistency of the FMU: CTF = CEF + CVF + CRF
        for n in names:
            fn = _ref.force_names(n)
            assert abs(got[fn["CT"]] - (got[fn["CE"]] + got[fn["CVF"]] + got[fn["CR"]])) <= 1e-12 * (
                abs(got[fn["CE"]]) + abs(got[fn["CVF"]]) + 1.0
            )
            assert got[fn["CR"]] == 0.0 or abs(got[fn["CR"]]) < 1e-12  # no stops
        for n in names:
            fn = _ref.force_names(n)
            k = dict(_ref.components_of(variant))[n]
            K, C = params[f"elasticity.k{k}"], params[f"damping.c{k}"]
            # k * (position error TOL_KIN); c * (rate error TOL_RATE)
            assert abs(got[fn["CE"]] - ref[fn["CE"]]) <= K * TOL_KIN * 2, (i, fn["CE"], got[fn["CE"]], ref[fn["CE"]])
            assert abs(got[fn["CVF"]] - C * got[fn["CV"]]) <= 1e-12 * max(1.0, abs(got[fn["CVF"]]))
            assert abs(got[fn["CVF"]] - ref[fn["CVF"]]) <= C * TOL_RATE, (i, fn["CVF"])
            assert abs(got[fn["CT"]] - ref[fn["CT"]]) <= K * TOL_KIN * 2 + C * TOL_RATE
        if variant == "Planar":
            kc, cc, kr = params["constraint.stiffness"], params["constraint.damping"], params["constraint.rotStiffness"]
            for n in ("CRF1", "CTF1"):
                assert abs(got[n] - ref[n]) <= kc * TOL_KIN * 2 + cc * TOL_RATE, (i, n, got[n], ref[n])
            for n in ("CRM2", "CTM2", "CRM3", "CTM3"):
                assert abs(got[n] - ref[n]) <= kr * TOL_KIN * 2, (i, n, got[n], ref[n])
        # energy: sum k u^2/2, errors k u TOL_KIN
        assert abs(got["energy.stored"] - ref["energy.stored"]) <= 1e-10 * max(1.0, ref["energy.stored"]), (
            got["energy.stored"],
            ref["energy.stored"],
        )
        L = node_loads(c)
        scale = _load_scale(ref)
        for n, v in L.items():
            assert np.linalg.norm(v - ref[n]) <= TOL_LOAD_REL * scale, (i, n, v, ref[n])


@pytest.mark.parametrize("variant", ALL)
def test_stretched_spring_sign(connect, variant):
    """Hand example (no reference code): node frames = world, a at 0, b
    initially at d0; reference.given = True with value 0 for every
    translational component (or rotational, for the projection types) so the
    spring is stretched; a positive stiffness gives CEF = k u_mat > 0 and
    pulls a towards b (a.f = +f, b.f = -f)."""
    k = 1000.0
    ident = np.array([1.0, 0, 0, 0])
    if variant == "ProjectionFlexionTorsion":
        th = 0.3
        pose = {"a.q": ident, "b.q": _ref.matrix_to_quat(_ref.rot_z(th))}
        params = {"elasticity.k6": k, "reference.given6": True, "reference.value6": 0.0}
        c = connect(variant, pose, params)
        got = c.named(["CPR3", "CEM3", "CTM3"])
        assert abs(got["CPR3"] - th) <= TOL_KIN and abs(got["CEM3"] - k * th) <= k * TOL_KIN
        # pure torsion: the moment resists the twist, m_b = -k th e3, m_a = +k th e3
        assert np.allclose(c.vec("b.m"), [0, 0, -k * th], atol=1e-9 * k)
        assert np.allclose(c.vec("a.m"), [0, 0, k * th], atol=1e-9 * k)
        return
    if variant == "Planar":
        d0 = np.array([0.0, 0.3, -0.2])  # y = 0.3, z = -0.2
        comps = {2: 0.3, 3: -0.2}
    elif variant == "RadialThrust":
        d0 = np.array([0.3, 0.4, 0.2])  # r = 0.5, l = 0.2
        comps = {1: 0.5, 3: 0.2}
    else:
        d0 = np.array([0.3, -0.4, 0.2])
        comps = {1: 0.3, 2: -0.4, 3: 0.2}
    pose = {"a.r": np.zeros(3), "a.q": ident, "b.r": d0, "b.q": ident}
    params = {}
    for kk in comps:
        params.update({f"elasticity.k{kk}": k, f"reference.given{kk}": True, f"reference.value{kk}": 0.0})
    if variant == "Planar":
        params.update({"constraint.stiffness": 1e5, "constraint.rotStiffness": 1e4})
    c = connect(variant, pose, params)
    got = c.named([f"CEF{kk}" for kk in comps])
    for kk, val in comps.items():
        assert abs(got[f"CEF{kk}"] - k * val) <= k * TOL_KIN, (kk, got)
    # force: Planar f = f2 e2 + f3 e3; RadialThrust f = f1 e_r + f3 e3a;
    # Cartesian at identity frames f = sum f_i e_i = k d0 -- in all three
    # cases f = k d0 here.
    f = k * d0
    assert np.allclose(c.vec("a.f"), f, atol=1e-9 * k) and np.allclose(c.vec("b.f"), -f, atol=1e-9 * k)


@pytest.mark.parametrize("variant", ["ProjectionCartesian", "Bushing", "RadialThrust"])
def test_damping_energy_constant_velocity(connect, variant):
    """Identity frames, a fixed, b moving at constant velocity v along world z
    (= e3, = e3a for RadialThrust) with linear extrapolation: CV3 = v, CVF3 =
    c v, CEF3 = k v t, energy.damping = c v^2 t and energy.stored =
    k (v t)^2 / 2 after N steps (closed form; the power is constant, so any
    quadrature is exact up to N round-offs: 1e-9 relative)."""
    k, cdamp, v, h, n = 300.0, 20.0, 0.5, 0.01, 50
    ident = np.array([1.0, 0, 0, 0])
    start = np.array([0.3, 0.4, 1.0])
    pose = {"a.r": np.zeros(3), "a.q": ident, "b.r": start, "b.q": ident, "b.v": np.array([0, 0, v])}
    c = connect(variant, pose, {"elasticity.k3": k, "damping.c3": cdamp, "cosim.extrapolation": 1})
    for i in range(1, n + 1):
        c.step(h)
        t = i * h
        got = c.named(["b.r[3]", "CV3", "CU3", "CEF3", "CVF3", "energy.damping", "energy.stored"])
        assert abs(got["b.r[3]"] - (1.0 + v * t)) <= 1e-12 * (1 + i)
        assert abs(got["CV3"] - v) <= 1e-12
        assert abs(got["CU3"] - v * t) <= 1e-12 * (1 + i)
        assert abs(got["CEF3"] - k * v * t) <= 1e-12 * k * (1 + i)
        assert abs(got["CVF3"] - cdamp * v) <= 1e-12 * cdamp
        assert abs(got["energy.damping"] - cdamp * v * v * t) <= 1e-9 * cdamp * v * v * t
        assert abs(got["energy.stored"] - 0.5 * k * (v * t) ** 2) <= 1e-9 * 0.5 * k * (v * t) ** 2


# ==========================================================================
# doStep extrapolation
# ==========================================================================


@pytest.mark.parametrize("variant", ALL)
def test_step_extrapolates_inputs(connect, variant):
    """cosim.extrapolation = 1: after fmi2DoStep(t, h) the inputs read back
    r + v h and exp(w h) q, and the outputs are those of that pose.  Looser
    tolerance (1e-10) since the FMU may compose the rotation in substeps (a
    few round-offs per substep)."""
    rng = np.random.default_rng(800 + ALL.index(variant))
    init = _ref.random_pose(rng, variant, with_velocity=True)
    c = connect(variant, init, {"cosim.extrapolation": 1})
    names = _positions_names(variant)
    P0 = _ref.positions(variant, init)
    prev = {k: P0[k] for k in ("CPR1", "CPR3") if k in P0}
    pose = init
    h = 0.02
    for _ in range(5):
        c.step(h)
        nxt = dict(pose)
        spec = _ref.VARIANTS[variant]
        for node in ("a", "b"):
            if "r" in spec[node]:
                nxt[f"{node}.r"] = pose[f"{node}.r"] + h * pose[f"{node}.v"]
            if "q" in spec[node]:
                nxt[f"{node}.q"] = _ref.quat_mul(_ref.quat_exp(h * pose[f"{node}.w"]), pose[f"{node}.q"])
        pose = nxt
        for node in ("a", "b"):
            if "r" in spec[node]:
                assert np.allclose(c.vec(f"{node}.r"), pose[f"{node}.r"], rtol=0, atol=1e-10)
            if "q" in spec[node]:
                got = c.named([f"{node}.q.{x}" for x in "wxyz"])
                qg = np.array([got[f"{node}.q.{x}"] for x in "wxyz"])
                # compare rotations (q and -q are the same rotation)
                assert np.allclose(_ref.quat_to_matrix(qg), _ref.quat_to_matrix(pose[f"{node}.q"]), rtol=0, atol=1e-10)
        ref = _ref.positions(variant, pose, prev)
        got = c.named(names)
        for n in names:
            assert abs(got[n] - ref[n]) <= 1e-10, (n, got[n], ref[n])
        prev = {k: ref[k] for k in ("CPR1", "CPR3") if k in ref}


@pytest.mark.parametrize("variant", ["Bushing", "RadialThrust"])
def test_step_hold_keeps_inputs(connect, variant):
    rng = np.random.default_rng(900)
    init = _ref.random_pose(rng, variant, with_velocity=True)
    c = connect(variant, init, {"cosim.extrapolation": 0})
    names = _positions_names(variant)
    before = c.named(names + ["a.r[1]", "b.r[2]"])
    for _ in range(3):
        c.step(0.05)
    after = c.named(names + ["a.r[1]", "b.r[2]"])
    for n in before:
        assert after[n] == pytest.approx(before[n], abs=1e-14), n


@pytest.mark.parametrize("variant", ALL)
def test_zero_velocity_step_leaves_outputs(connect, variant):
    rng = np.random.default_rng(950 + ALL.index(variant))
    init = _ref.random_pose(rng, variant, with_velocity=False)
    c = connect(variant, init, _spring_params(variant, rng, damping=True))
    pose = _ref.random_pose(rng, variant, with_velocity=False)
    set_pose(c, pose)
    names = _positions_names(variant) + ["energy.stored"]
    before, L0 = c.named(names), node_loads(c)
    c.step(0.1)
    after, L1 = c.named(names), node_loads(c)
    for n in names:
        assert after[n] == pytest.approx(before[n], rel=1e-13, abs=1e-13), n
    for n in L0:
        assert np.allclose(L1[n], L0[n], rtol=1e-13, atol=1e-13 * _load_scale(L0))


# ==========================================================================
# 9. loads = - d(energy.stored)/d(node motion), through the FMU
# ==========================================================================


@pytest.mark.parametrize("variant", ["Bushing", "RadialThrust", "Planar", "ProjectionFlexionTorsion", "ProjectionCartesian"])
def test_loads_are_energy_gradient(connect, variant):
    """A purely elastic connector is conservative: every node-load component
    equals -(E(+h) - E(-h)) / 2h with E = energy.stored read from the FMU after
    moving the node by +-h, +-2h (translation along a world axis, or a
    world-frame rotation about the node: q <- exp(s h e_j) q), combined in the
    fourth-order central difference.  h = 5e-4: truncation h^4 E^(5) / 30 and
    cancellation 1.5 eps E / h are both ~1e-12 of the load scale (measured
    <= 3e-12 on the current FMU; a plain two-point difference with h = 1e-6
    would only reach ~5e-10); tested at 1e-10 of the load scale.  Planar includes the penalty springs
    (constraint.stiffness, constraint.rotStiffness): their energy is stored
    energy, as the energy balance of docs/physics.md, Behaviours needs."""
    rng = np.random.default_rng(1000 + ALL.index(variant))
    params = _spring_params(variant, rng, damping=False)
    init = _ref.random_pose(rng, variant, with_velocity=False)
    c = connect(variant, init, params)
    h = 5e-4
    stencil = {2: -1.0 / 12.0, 1: 8.0 / 12.0, -1: -8.0 / 12.0, -2: 1.0 / 12.0}
    spec = _ref.VARIANTS[variant]
    for _ in range(5):
        pose = _ref.random_pose(rng, variant, with_velocity=False)
        set_pose(c, pose)
        L = node_loads(c)
        scale = _load_scale(L)
        assert scale > 1.0
        for node, kind, j in _ref.MOTIONS:
            load_name = f"{node}.{'f' if kind == 'r' else 'm'}"
            if kind not in spec[node]:
                continue  # no such input (e.g. RadialThrust b.q)
            dE = 0.0
            for s, w in stencil.items():
                set_pose(c, _ref.perturb(pose, node, kind, j, s * h))
                dE += w * c.named(["energy.stored"])["energy.stored"]
            set_pose(c, pose)
            fd = -dE / h
            have = L[load_name][j] if load_name in L else 0.0
            assert abs(fd - have) <= 1e-10 * scale, (load_name, j, fd, have)
