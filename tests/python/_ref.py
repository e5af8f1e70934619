"""Independent numpy reference for the connector kinematics and loads.

Written from the Abaqus manual pages in the seed (PROJECTION CARTESIAN,
PROJECTION FLEXION-TORSION, RADIAL-THRUST, PLANAR) and docs/physics.md (Kinematics) only;
it shares no code with the Rust implementation, so a test comparing the FMU
against it is a real cross-check.

Conventions (README, Conventions):
  * quaternions are scalar first (w, x, y, z) and map node-local coordinates
    to the world frame; e_i^a is column i of R(q_a);
  * d = x_b - x_a;
  * a small rotation of a node is applied in the world frame,
    q <- exp(theta) * q, about the node's own position.

Node loads are obtained by virtual work (README, Conventions): the load on a node is
-sum_i F_i dc_i/d(node motion).  The gradients dc_i/d(node motion) are taken by
fourth-order central finite differences of this reference kinematics (step
h = 5e-4), which keeps the reference free of any hand-derived (and possibly
shared) gradient formula.  Error of that difference: truncation
~ h^4 |c^(5)| / 30 ~ 1e-13 and round-off ~ 1.5 eps |c| / h ~ 1e-12 for O(1)
components (|d| <= ~2.5 m, angles <= 2.5 rad), i.e. ~1e-12 relative.
"""

from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * math.pi

# --------------------------------------------------------------------------
# rotations
# --------------------------------------------------------------------------


def quat_normalize(q):
    q = np.asarray(q, dtype=float)
    n = np.linalg.norm(q)
    if not np.isfinite(n) or n < 1e-6:
        raise ValueError(f"quaternion norm {n} is not usable")
    return q / n


def quat_to_matrix(q):
    """Rotation matrix of a (normalised) scalar-first quaternion."""
    w, x, y, z = quat_normalize(q)
    return np.array(
        [
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
            [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
            [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
        ]
    )


def matrix_to_quat(R):
    """Scalar-first unit quaternion of a rotation matrix (Shepperd), w >= 0."""
    R = np.asarray(R, dtype=float)
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    cands = [tr, R[0, 0], R[1, 1], R[2, 2]]
    i = int(np.argmax(cands))
    if i == 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif i == 1:
        s = 2.0 * math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif i == 2:
        s = 2.0 * math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    if q[0] < 0.0:
        q = -q
    return q / np.linalg.norm(q)


def quat_mul(p, q):
    """Hamilton product p*q (scalar first)."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return np.array(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ]
    )


def quat_exp(phi):
    """Unit quaternion of the rotation vector phi (angle |phi| about phi/|phi|)."""
    phi = np.asarray(phi, dtype=float)
    th = float(np.linalg.norm(phi))
    if th == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[math.cos(0.5 * th)], math.sin(0.5 * th) * phi / th])


def rotvec_to_matrix(phi):
    """Rodrigues: rotation matrix of the rotation vector phi."""
    phi = np.asarray(phi, dtype=float)
    th = float(np.linalg.norm(phi))
    K = np.array([[0.0, -phi[2], phi[1]], [phi[2], 0.0, -phi[0]], [-phi[1], phi[0], 0.0]])
    if th < 1e-8:
        # series, exact to double precision for th < 1e-8
        return np.eye(3) + K + 0.5 * K @ K
    return np.eye(3) + (math.sin(th) / th) * K + ((1.0 - math.cos(th)) / (th * th)) * (K @ K)


def rot_x(t):
    return rotvec_to_matrix([t, 0.0, 0.0])


def rot_y(t):
    return rotvec_to_matrix([0.0, t, 0.0])


def rot_z(t):
    return rotvec_to_matrix([0.0, 0.0, t])


def nearest_branch(principal, prev, period):
    """principal + m*period with the integer m that puts it closest to prev."""
    return principal + period * round((prev - principal) / period)


# --------------------------------------------------------------------------
# kinematics of the manual / docs/physics.md, Kinematics
# --------------------------------------------------------------------------


def centred_triad(Ra, Rb, beta_prev=0.0):
    """Centred projection triad of docs/physics.md, Kinematics.

    Returns (E, alpha1, alpha2, beta) with E the 3x3 matrix whose columns are
    e1, e2, e3.  beta is continued (2*pi*m) towards beta_prev.
    """
    e1a, e2a, e3a = Ra[:, 0], Ra[:, 1], Ra[:, 2]
    e1b, e2b, e3b = Rb[:, 0], Rb[:, 1], Rb[:, 2]
    cross = np.cross(e3a, e3b)
    s = float(np.linalg.norm(cross))  # sin(alpha)
    c = float(e3a @ e3b)  # cos(alpha)
    alpha = math.atan2(s, c)  # = acos(e3a.e3b) of the seed, 0 <= alpha <= pi
    if alpha > math.pi - 1e-6:
        raise ValueError("flexion angle at pi: singular")
    # alpha*q = (alpha / sin alpha) (e3a x e3b), smooth as alpha -> 0
    factor = alpha / s if s > 1e-10 else 1.0 + alpha * alpha / 6.0
    alpha_q = factor * cross
    # step 1: bisector of the shaft axes
    e3 = (e3a + e3b) / np.linalg.norm(e3a + e3b)
    # step 2: frame a rotated by +alpha/2 about q
    Ra_c = rotvec_to_matrix(0.5 * alpha_q) @ Ra
    # step 3: torsion (seed formula, 2*pi branch by continuity)
    num = float(e2a @ e1b - e1a @ e2b)
    den = float(e1a @ e1b + e2a @ e2b)
    beta = nearest_branch(math.atan2(num, den), beta_prev, TWO_PI)
    # step 4: rotate by beta/2 about e3
    E = rotvec_to_matrix(0.5 * beta * e3) @ Ra_c
    alpha1 = float(E[:, 0] @ alpha_q)
    alpha2 = float(E[:, 1] @ alpha_q)
    return E, alpha1, alpha2, beta


def flexion_angle(Ra, Rb):
    """alpha = acos(e3a . e3b) exactly as the seed writes it."""
    return math.acos(max(-1.0, min(1.0, float(Ra[:, 2] @ Rb[:, 2]))))


def cartesian(d, E):
    """PROJECTION CARTESIAN: (x, y, z) = (e1.d, e2.d, e3.d)."""
    return E.T @ np.asarray(d, dtype=float)


def radial_thrust(d, Ra):
    """RADIAL-THRUST: (r, l, e_r) as in the seed."""
    d = np.asarray(d, dtype=float)
    e1a, e2a, e3a = Ra[:, 0], Ra[:, 1], Ra[:, 2]
    p1, p2 = float(e1a @ d), float(e2a @ d)
    r = math.hypot(p1, p2)
    l = float(e3a @ d)
    e_r = (p1 * e1a + p2 * e2a) / r
    return r, l, e_r


def planar(d, Ra, Rb, alpha_prev=0.0):
    """PLANAR = SLIDE-PLANE + REVOLUTE (docs/physics.md, Kinematics).

    Returns dict with x (constrained, e1a.d), y, z, alpha (+n*pi branch by
    continuity towards alpha_prev) and the misalignment phi2 = -e3a.e1b,
    phi3 = e2a.e1b that the penalty moments m2, m3 act on.
    """
    d = np.asarray(d, dtype=float)
    e1a, e2a, e3a = Ra[:, 0], Ra[:, 1], Ra[:, 2]
    e1b, e3b = Rb[:, 0], Rb[:, 2]
    # -atan(n/dn) and -atan2(n, dn) differ by a multiple of pi, so the
    # continuation below gives the seed's atan(...) + n*pi branch.
    alpha = nearest_branch(-math.atan2(float(e2a @ e3b), float(e3a @ e3b)), alpha_prev, math.pi)
    return {
        "x": float(e1a @ d),
        "y": float(e2a @ d),
        "z": float(e3a @ d),
        "alpha": alpha,
        "phi2": float(-(e3a @ e1b)),
        "phi3": float(e2a @ e1b),
    }


# --------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------

#: per variant: translational / rotational component indices (within the
#: triple), which node inputs exist, which node-load outputs exist.
VARIANTS = {
    "Planar": dict(trans=[2, 3], rot=[1], a="rqvw", b="rqvw", loads=["a.f", "a.m", "b.f", "b.m"]),
    "ProjectionCartesian": dict(trans=[1, 2, 3], rot=[], a="rqvw", b="rqvw", loads=["a.f", "a.m", "b.f", "b.m"]),
    "ProjectionFlexionTorsion": dict(trans=[], rot=[1, 2, 3], a="qw", b="qw", loads=["a.m", "b.m"]),
    "Bushing": dict(trans=[1, 2, 3], rot=[1, 2, 3], a="rqvw", b="rqvw", loads=["a.f", "a.m", "b.f", "b.m"]),
    "RadialThrust": dict(trans=[1, 3], rot=[], a="rqvw", b="rv", loads=["a.f", "a.m", "b.f"]),
}

#: Planar's penalty-constrained coordinates (not FMU outputs by these names).
PLANAR_CONSTRAINED = ["X1", "PHI2", "PHI3"]


def components_of(variant):
    """Names of the available position outputs, e.g. ['CP1', 'CPR1'], with the
    Abaqus component number k (1..6) of each."""
    spec = VARIANTS[variant]
    return [(f"CP{i}", i) for i in spec["trans"]] + [(f"CPR{i}", 3 + i) for i in spec["rot"]]


def force_names(cp_name):
    """(CU, CV, CTF, CEF, CVF, CRF) output names belonging to a position name."""
    if cp_name.startswith("CPR"):
        i = cp_name[3:]
        return dict(CU=f"CUR{i}", CV=f"CVR{i}", CT=f"CTM{i}", CE=f"CEM{i}", CVF=f"CVM{i}", CR=f"CRM{i}")
    i = cp_name[2:]
    return dict(CU=f"CU{i}", CV=f"CV{i}", CT=f"CTF{i}", CE=f"CEF{i}", CVF=f"CVF{i}", CR=f"CRF{i}")


def input_names(variant):
    """FMU input variable names of the variant, in a fixed order: the poses and twists, then the
    accelerations of the velocities the variant has (v -> dv, w -> dw)."""
    spec = VARIANTS[variant]
    names = []
    for node in ("a", "b"):
        for kind in spec[node]:
            if kind == "q":
                names += [f"{node}.q.{c}" for c in "wxyz"]
            else:
                names += [f"{node}.{kind}[{j}]" for j in (1, 2, 3)]
    for node in ("a", "b"):
        for kind in spec[node]:
            if kind in "vw":
                names += [f"{node}.d{kind}[{j}]" for j in (1, 2, 3)]
    return names


def pose_to_inputs(variant, pose):
    """Map a pose dict {'a.r': (3,), 'a.q': (4,), 'a.v', 'a.w', 'b.*'} to the
    variant's FMU input values (missing velocities are zero)."""
    spec = VARIANTS[variant]
    out = {}
    for node in ("a", "b"):
        for kind in spec[node]:
            key = f"{node}.{kind}"
            if kind == "q":
                val = np.asarray(pose[key], dtype=float)
                for c, v in zip("wxyz", val):
                    out[f"{node}.q.{c}"] = float(v)
            else:
                val = np.asarray(pose.get(key, np.zeros(3)), dtype=float)
                for j in range(3):
                    out[f"{node}.{kind}[{j + 1}]"] = float(val[j])
    return out


def positions(variant, pose, prev=None):
    """Component positions of the variant at pose.

    prev: dict with the previous branch values {'CPR3': beta} (centred types)
    or {'CPR1': alpha} (Planar); missing means 0.
    Returns dict name -> value: the available CP<i>/CPR<i> and, for Planar,
    the constrained coordinates X1 (= e1a.d), PHI2, PHI3.
    """
    prev = prev or {}
    Ra = quat_to_matrix(pose["a.q"]) if "a.q" in pose else np.eye(3)
    Rb = quat_to_matrix(pose["b.q"]) if "b.q" in pose else np.eye(3)
    d = np.asarray(pose.get("b.r", np.zeros(3)), float) - np.asarray(pose.get("a.r", np.zeros(3)), float)
    out = {}
    if variant in ("ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing"):
        E, a1, a2, beta = centred_triad(Ra, Rb, prev.get("CPR3", 0.0))
        if variant != "ProjectionFlexionTorsion":
            x, y, z = cartesian(d, E)
            out.update(CP1=x, CP2=y, CP3=z)
        if variant != "ProjectionCartesian":
            out.update(CPR1=a1, CPR2=a2, CPR3=beta)
    elif variant == "RadialThrust":
        r, l, _ = radial_thrust(d, Ra)
        out.update(CP1=r, CP3=l)
    elif variant == "Planar":
        p = planar(d, Ra, Rb, prev.get("CPR1", 0.0))
        out.update(CP2=p["y"], CP3=p["z"], CPR1=p["alpha"], X1=p["x"], PHI2=p["phi2"], PHI3=p["phi3"])
    else:
        raise KeyError(variant)
    return {k: float(v) for k, v in out.items()}


def triad(pose, beta_prev=0.0):
    """The centred triad E (columns e1, e2, e3) at pose."""
    return centred_triad(quat_to_matrix(pose["a.q"]), quat_to_matrix(pose["b.q"]), beta_prev)[0]


# --------------------------------------------------------------------------
# node motions and gradients
# --------------------------------------------------------------------------

#: the 12 generalised node motions, in this order
MOTIONS = [(node, kind, j) for node in ("a", "b") for kind in ("r", "q") for j in range(3)]


def perturb(pose, node, kind, j, eps):
    """Pose with node translated by eps along world axis j (kind 'r') or rotated
    by eps about world axis j about its own position (kind 'q':
    q <- exp(eps e_j) q)."""
    p = {k: np.array(v, dtype=float) for k, v in pose.items()}
    if kind == "r":
        p[f"{node}.r"] = p.get(f"{node}.r", np.zeros(3)).copy()
        p[f"{node}.r"][j] += eps
    else:
        phi = np.zeros(3)
        phi[j] = eps
        p[f"{node}.q"] = quat_mul(quat_exp(phi), p.get(f"{node}.q", np.array([1.0, 0, 0, 0])))
    return p


def gradients(variant, pose, prev=None, h=5e-4):
    """d(component)/d(node motion) by the fourth-order central difference
    (-c(2h) + 8 c(h) - 8 c(-h) + c(-2h)) / 12h.

    Returns dict name -> (12,) array over MOTIONS.  The branch of every
    perturbed evaluation is continued from the unperturbed value.
    """
    base = positions(variant, pose, prev)
    cont = {k: base[k] for k in ("CPR1", "CPR3") if k in base}
    G = {k: np.zeros(12) for k in base}
    for m, (node, kind, j) in enumerate(MOTIONS):
        c = {s: positions(variant, perturb(pose, node, kind, j, s * h), cont) for s in (2, 1, -1, -2)}
        for k in base:
            G[k][m] = (-c[2][k] + 8.0 * c[1][k] - 8.0 * c[-1][k] + c[-2][k]) / (12.0 * h)
    return G


def motion_rates(pose):
    """The 12 generalised velocities (v_a, w_a, v_b, w_b) of a pose."""
    z = np.zeros(3)
    return np.concatenate(
        [np.asarray(pose.get(k, z), dtype=float) for k in ("a.v", "a.w", "b.v", "b.w")]
    )


def velocities(variant, pose, prev=None, h=5e-4):
    """Component rates along the velocity inputs (relative velocities CV)."""
    G = gradients(variant, pose, prev, h)
    rates = motion_rates(pose)
    return {k: float(g @ rates) for k, g in G.items()}


def node_loads(G, forces):
    """Virtual work: load on the nodes = -sum F_i grad c_i.

    forces: dict component name -> generalised force conjugate to it.
    Returns dict 'a.f', 'a.m', 'b.f', 'b.m' -> (3,) arrays.
    """
    g = np.zeros(12)
    for k, F in forces.items():
        g -= F * G[k]
    return {"a.f": g[0:3], "a.m": g[3:6], "b.f": g[6:9], "b.m": g[9:12]}


# --------------------------------------------------------------------------
# the full constitutive reference
# --------------------------------------------------------------------------


def connector(variant, pose, init_pose, params, h=5e-4, prev=None):
    """Expected FMU outputs at pose after initialization at init_pose.

    params: dict of FMU parameter names (elasticity.k<k>, damping.c<k>,
    reference.given<k>, reference.value<k>, constraint.*) -> values; missing
    entries are 0 / False.  The torsion branch is continued from prev
    ({'CPR3': beta} or {'CPR1': alpha}), by default from the initial pose.

    Returns dict output name -> float, or (3,) arrays for node loads, plus
    'energy.stored'.
    """
    P0 = positions(variant, init_pose)
    if prev is None:
        prev = {k: P0[k] for k in ("CPR1", "CPR3") if k in P0}
    P = positions(variant, pose, prev)
    G = gradients(variant, pose, prev, h)
    rates = motion_rates(pose)
    V = {k: float(g @ rates) for k, g in G.items()}

    out = {}
    forces = {}
    energy = 0.0
    for name, k in components_of(variant):
        n = force_names(name)
        ref = params.get(f"reference.value{k}", 0.0) if params.get(f"reference.given{k}", False) else P0[name]
        u_mat = P[name] - ref
        K = params.get(f"elasticity.k{k}", 0.0)
        C = params.get(f"damping.c{k}", 0.0)
        out[name] = P[name]
        out[n["CU"]] = P[name] - P0[name]
        out[n["CV"]] = V[name]
        out[n["CE"]] = K * u_mat
        out[n["CVF"]] = C * V[name]
        out[n["CT"]] = out[n["CE"]] + out[n["CVF"]]
        forces[name] = out[n["CT"]]
        energy += 0.5 * K * u_mat * u_mat
    if variant == "Planar":
        kc = params.get("constraint.stiffness", 0.0)
        cc = params.get("constraint.damping", 0.0)
        kr = params.get("constraint.rotStiffness", 0.0)
        cr = params.get("constraint.rotDamping", 0.0)
        f1 = kc * (P["X1"] - P0["X1"]) + cc * V["X1"]
        m2 = kr * P["PHI2"] + cr * V["PHI2"]
        m3 = kr * P["PHI3"] + cr * V["PHI3"]
        out.update(CRF1=f1, CTF1=f1, CRM2=m2, CTM2=m2, CRM3=m3, CTM3=m3)
        forces.update(X1=f1, PHI2=m2, PHI3=m3)
        energy += 0.5 * kc * (P["X1"] - P0["X1"]) ** 2 + 0.5 * kr * (P["PHI2"] ** 2 + P["PHI3"] ** 2)
    out.update(node_loads(G, forces))
    out["energy.stored"] = energy
    return out


# --------------------------------------------------------------------------
# pose generators
# --------------------------------------------------------------------------


def random_rotation(rng, max_angle):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    return rotvec_to_matrix(axis * rng.uniform(0.0, max_angle))


def random_pose(rng, variant, *, max_flexion=2.5, max_torsion=0.75, max_node_rot=1.5, with_velocity=True):
    """A random pose of both nodes whose branch angles are safe.

    Node a: rotation of up to max_node_rot.  Node b relative to a:
      * centred types: Rz(phi) Ry(alpha) Rz(beta - phi) with alpha up to
        max_flexion and torsion beta in +-max_torsion, so that any two poses'
        torsions differ by less than pi/2 and every continuation rule (nearest
        to 0, to the initial value, to the last value, with pi or 2 pi) picks
        the principal value;
      * Planar: Rx(alpha) with alpha in +-max_torsion and a misalignment of
        e1b of up to 0.1 rad;
      * RadialThrust: any rotation (ignored); radial distance > 0.2 m.
    """
    Ra = random_rotation(rng, max_node_rot)
    if variant == "Planar":
        Rrel = rot_x(rng.uniform(-max_torsion, max_torsion)) @ random_rotation(rng, 0.1)
    else:
        phi = rng.uniform(-math.pi, math.pi)
        beta = rng.uniform(-max_torsion, max_torsion)
        Rrel = rot_z(phi) @ rot_y(rng.uniform(0.0, max_flexion)) @ rot_z(beta - phi)
    Rb = Ra @ Rrel
    xa = rng.uniform(-1.0, 1.0, size=3)
    while True:
        dvec = rng.normal(size=3)
        dvec *= rng.uniform(0.3, 2.0) / np.linalg.norm(dvec)
        if variant != "RadialThrust" or math.hypot(Ra[:, 0] @ dvec, Ra[:, 1] @ dvec) > 0.2:
            break
    pose = {"a.r": xa, "a.q": matrix_to_quat(Ra), "b.r": xa + dvec, "b.q": matrix_to_quat(Rb)}
    if with_velocity:
        for k in ("a.v", "a.w", "b.v", "b.w"):
            pose[k] = rng.uniform(-1.0, 1.0, size=3)
    else:
        for k in ("a.v", "a.w", "b.v", "b.w"):
            pose[k] = np.zeros(3)
    return pose


def rigid_motion(pose, Q, t, omega=None, v0=None):
    """Apply x -> Q x + t, R -> Q R to both nodes; optionally replace the
    velocities by the rigid field v = v0 + omega x x, w = omega."""
    out = dict(pose)
    qQ = matrix_to_quat(Q)
    for node in ("a", "b"):
        out[f"{node}.r"] = Q @ np.asarray(pose[f"{node}.r"], float) + t
        out[f"{node}.q"] = quat_mul(qQ, quat_normalize(pose[f"{node}.q"]))
        if omega is not None:
            out[f"{node}.w"] = np.asarray(omega, float).copy()
            out[f"{node}.v"] = np.asarray(v0, float) + np.cross(omega, out[f"{node}.r"])
    return out
