"""The Body FMU's load ports (docs/body.md, "Load ports") through fmpy: today's variables step
exactly as before the ports existed (bit for bit against a recording of the FMU of commit
19c4af4, tests/data/body_before_ports.json: 120 random loads and steps of each model, FMI 2.0
and 3.0); a port's outputs are its offset carried by the body (r + R p, q ⊗ q_off,
v + ω × R p, ω); the loads sum about the centre of mass (a force at an offset is that force
and the moment R p × f at the centre); a connector FMU between two ports gives the same motion
as the same connector whose node kinematics and loads are carried to and from the centres by
hand; and a free system of two bodies on one elastic Bushing keeps its momentum to round-off
and its energy and angular momentum to the first order in H of the Jacobi coupling.

Tolerances: a port output against its formula 16 ulp of its scale (a handful of roundings of
the 3x3 product and the cross product); "same motion" comparisons 1e-12 of the scale over
200 steps (the two paths round R p, d x f and the sums in different orders; over 200 steps of
a bounded elastic system round-off grows a few hundred ulp, not more); momentum 1e-13 of
m|v| (the connector's loads balance to round-off, f_a + f_b = 0 exactly for an elastic
connector, docs/physics.md, and each step adds a few ulp).
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from conftest import REPO
from cosim import driver
from cosim.bodies import quat_matrix, quat_mul
from test_body_fmu import OUT, Body

EPS = np.finfo(float).eps
BEFORE = REPO / "tests" / "data" / "body_before_ports.json"
STATE = ["r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z", "v[1]", "v[2]", "v[3]", "w[1]", "w[2]", "w[3]"]


def port_names(k, kind):
    if kind == "q":
        return [f"port[{k}].q.{c}" for c in "wxyz"]
    return [f"port[{k}].{kind}[{i}]" for i in (1, 2, 3)]


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("case", ["axes", "rigid"])
def test_todays_variables_step_bit_for_bit_as_before_the_ports(version, case):
    """Recorded with the Body FMU of commit 19c4af4 (before the ports) by driving it through
    this file's Body helper with the recorded loads and steps; the FMU of today must give every
    output back to the last bit."""
    rec = json.loads(BEFORE.read_text())
    assert rec["outputs"] == OUT
    c = rec["cases"][case]
    b = Body(version, c["params"], c["ints"])
    got = [[float(b.initial[n]).hex() for n in OUT]]
    for h, f, m in c["steps"]:
        o = b.step(float.fromhex(h), [float.fromhex(x) for x in f], [float.fromhex(x) for x in m])
        got.append([float(o[n]).hex() for n in OUT])
    b.close()
    assert got == c["outputs"]


def rigid_params(**extra):
    q0 = np.array([0.9, 0.1, 0.3, -0.3]) / np.linalg.norm([0.9, 0.1, 0.3, -0.3])
    p = {"mass": 3.0, "inertia[1]": 1.0, "inertia[2]": 2.0, "inertia[3]": 3.0,
         "start.r[1]": 0.3, "start.r[2]": -0.2, "start.r[3]": 1.0,
         **dict(zip(["start.q.w", "start.q.x", "start.q.y", "start.q.z"], map(float, q0))),
         "start.v[1]": 0.2, "start.v[3]": -0.1, "start.w[1]": 1.0, "start.w[2]": 4.0, "start.w[3]": 0.5}
    p.update(extra)
    return p


OFFSETS = {1: ([0.25, -0.1, 0.4], [1.0, 0.0, 0.0, 0.0]),
           2: ([-0.3, 0.2, 0.0], [2.0, 0.2, -0.4, 0.6]),          # not normalised: the FMU normalises
           3: ([0.0, 0.0, -0.5], [math.cos(0.3), math.sin(0.3), 0.0, 0.0]),
           4: ([0.1, 0.1, 0.1], [0.0, 0.0, 0.0, 1.0])}


def offset_params(offsets):
    p = {}
    for k, (r, q) in offsets.items():
        p.update({f"port[{k}].offset.r[{i + 1}]": float(r[i]) for i in range(3)})
        p.update({f"port[{k}].offset.q.{c}": float(q[i]) for i, c in enumerate("wxyz")})
    return p


def expected_port(o, r_off, q_off):
    """(r, q, v, w) of a port from the body's outputs `o`, numpy's formulas."""
    q = np.array([o[n] for n in ["q.w", "q.x", "q.y", "q.z"]])
    r = np.array([o[f"r[{i}]"] for i in (1, 2, 3)])
    v = np.array([o[f"v[{i}]"] for i in (1, 2, 3)])
    w = np.array([o[f"w[{i}]"] for i in (1, 2, 3)])
    d = quat_matrix(q) @ np.asarray(r_off)
    q_off = np.asarray(q_off) / np.linalg.norm(q_off)
    return r + d, quat_mul(q, q_off), v + np.cross(w, d), w


@pytest.mark.parametrize("version", [2, 3])
def test_port_outputs_are_the_offset_carried_by_the_body(version):
    b = Body(version, {**rigid_params(), **offset_params(OFFSETS)}, {"model": 1})
    rng = np.random.default_rng(3)
    for n in range(60):
        if n % 20 == 0:          # in Initialization Mode (n = 0) and after steps
            o = dict(zip(STATE, b.get(STATE)))
            for k, (r_off, q_off) in OFFSETS.items():
                want = expected_port(o, r_off, q_off)
                for kind, x in zip("rqvw", want):
                    got = b.get(port_names(k, kind))
                    scale = max(1.0, np.abs(x).max())
                    assert np.abs(got - x).max() <= 16 * EPS * scale, (k, kind, got, x)
                qk = b.get(port_names(k, "q"))
                assert abs(np.linalg.norm(qk) - 1.0) <= 4 * EPS
        b.step(0.01, rng.normal(0, 3, 3), rng.normal(0, 1, 3))
    b.close()


def test_the_model_0_port_turns_with_the_turning_axis():
    """Model 0, turning about z at 2 rad/s: a port at (0.5, 0, 0) is on the circle of radius 0.5."""
    b = Body(2, {"start.w[3]": 2.0, **offset_params({1: ([0.5, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0])})},
             {"dof.r[1]": 0, "dof.r[2]": 0, "dof.r[3]": 0, "dof.w[3]": 2})
    for _ in range(100):
        b.step(0.01)
    th = 2.0 * b.t
    assert np.abs(b.get(port_names(1, "r")) - [0.5 * math.cos(th), 0.5 * math.sin(th), 0.0]).max() <= 1e-14
    assert np.abs(b.get(port_names(1, "v")) - [-math.sin(th), math.cos(th), 0.0]).max() <= 1e-14
    b.close()


@pytest.mark.parametrize("model", [0, 1])
def test_a_force_at_an_offset_is_the_force_and_its_moment_at_the_centre(model):
    """Body A: loads on all four ports (forces and moments) and on its own f, m; body B: only
    its own f, m, set to f + Σ f_k and m + Σ (m_k + R p_k × f_k) computed by hand. Same motion."""
    ints = {"model": 1} if model == 1 else {"dof.w[3]": 1}
    params = rigid_params() if model == 1 else {"mass": 3.0, "inertia[3]": 2.0, "start.w[3]": 1.0}
    a = Body(2, {**params, **offset_params(OFFSETS)}, ints)
    b = Body(2, params, ints)
    rng = np.random.default_rng(5)
    for _ in range(200):
        o = dict(zip(STATE, a.get(STATE)))
        R = quat_matrix(np.array([o[n] for n in ["q.w", "q.x", "q.y", "q.z"]]))
        own_f, own_m = rng.normal(0, 2, 3), rng.normal(0, 1, 3)
        f_sum, m_sum, values = own_f.copy(), own_m.copy(), {}
        for k, (r_off, _) in OFFSETS.items():
            fk, mk = rng.normal(0, 2, 3), rng.normal(0, 1, 3)
            values.update({f"port[{k}].f[{i + 1}]": fk[i] for i in range(3)})
            values.update({f"port[{k}].m[{i + 1}]": mk[i] for i in range(3)})
            f_sum += fk
            m_sum += mk + np.cross(R @ np.asarray(r_off), fk)
        a.set(values)
        oa, ob = a.step(0.01, own_f, own_m), b.step(0.01, f_sum, m_sum)
    for n in STATE:
        scale = max(1.0, abs(ob[n]))
        assert abs(oa[n] - ob[n]) <= 1e-12 * scale, (n, oa[n], ob[n])
    a.close()
    b.close()


class Fmu(driver.Connector):
    """A Body or connector FMU (FMI 2.0) by name, started with `params` and `inputs`."""

    def __init__(self, model, name, params, inputs=None):
        super().__init__(model, driver.instantiate(model, driver.unzipped(model), instance_name=name))
        self.start(params, inputs or {})

    def close(self):
        self.s.terminate()
        self.s.freeInstance()


LOADS = [f"{x}[{i}]" for x in "fm" for i in (1, 2, 3)]
BUSHING = {**{f"elasticity.k{i}": k for i, k in enumerate([400.0, 500.0, 600.0, 20.0, 30.0, 40.0], 1)},
           "cosim.extrapolation": 0}
DAMPING = {f"damping.c{i}": c for i, c in enumerate([0.5, 0.5, 0.5, 0.01, 0.01, 0.01], 1)}
KA, KB = 2, 3                 # A's port 2 and B's port 3 (offset frames not the body frame)


class Pair:
    """Two rigid bodies A and B (B 0.6 m along x from A) on one Bushing, coupled by a Jacobi
    loop: node a at A's point OFFSETS[KA], node b at B's OFFSETS[KB]. `via_ports`: the FMU's
    ports carry the node kinematics and the loads; otherwise the loop carries them by hand
    from and to the centres (numpy's formulas: r + R p, q ⊗ q_off, v + ω × R p, ω; f and
    m + R p × f). `offsets=False` puts both points at the centres."""

    def __init__(self, via_ports, offsets=True, damping=True):
        self.via_ports = via_ports
        self.off = {"a": OFFSETS[KA] if offsets else ([0.0] * 3, [1.0, 0, 0, 0]),
                    "b": OFFSETS[KB] if offsets else ([0.0] * 3, [1.0, 0, 0, 0])}
        pa = rigid_params()
        pb = rigid_params(**{"start.r[1]": 0.9, "start.w[1]": -0.5, "start.v[2]": 0.3})
        if via_ports:
            pa.update(offset_params({KA: self.off["a"]}))
            pb.update(offset_params({KB: self.off["b"]}))
        self.body = {"a": Fmu("Body", "A", {"model": 1, **pa}), "b": Fmu("Body", "B", {"model": 1, **pb})}
        self.port = {"a": KA, "b": KB}
        self.c = Fmu("Bushing", "bushing", {**BUSHING, **(DAMPING if damping else {})}, self.nodes())
        self.t = 0.0

    def node(self, n):
        body = self.body[n]
        if self.via_ports:
            k = self.port[n]
            return body.get(sum((port_names(k, x) for x in "rqvw"), []))
        return np.concatenate(expected_port(body.named(STATE), *self.off[n]))

    def nodes(self):
        return {f"{n}.{x}": v for n in "ab" for x, v in zip(STATE, self.node(n))}

    def step(self, H):
        for n in "ab":
            load = self.c.get([f"{n}.{x}" for x in LOADS])
            if self.via_ports:
                self.body[n].set({f"port[{self.port[n]}].{x}": v for x, v in zip(LOADS, load)})
            else:
                q = self.body[n].get(["q.w", "q.x", "q.y", "q.z"])
                d = quat_matrix(q) @ np.asarray(self.off[n][0])
                m = load[3:] + np.cross(d, load[:3])
                self.body[n].set(dict(zip(LOADS, [*load[:3], *m])))
        for f in (*self.body.values(), self.c):
            f.step(H)
        self.c.set(self.nodes())
        self.t += H

    def state(self):
        return np.concatenate([self.body[n].get(STATE) for n in "ab"])

    def close(self):
        for f in (*self.body.values(), self.c):
            f.close()


def run(pair, H, n):
    rows = [pair.state()]
    for _ in range(n):
        pair.step(H)
        rows.append(pair.state())
    pair.close()
    return np.array(rows)


def test_a_connector_between_ports_moves_as_the_same_connector_carried_to_the_centres():
    ports, by_hand = run(Pair(True), 2e-3, 200), run(Pair(False), 2e-3, 200)
    scale = np.maximum(1.0, np.abs(by_hand).max(axis=0))
    assert (np.abs(ports - by_hand) / scale).max() <= 1e-12
    # the bodies did move relative to each other: the Bushing worked (not a trivially equal run)
    assert np.abs(by_hand[-1] - by_hand[0]).max() > 0.1


def test_ports_at_the_centres_are_the_centres_bit_for_bit():
    ports, centres = run(Pair(True, offsets=False), 2e-3, 200), run(Pair(False, offsets=False), 2e-3, 200)
    assert np.array_equal(ports, centres)


def invariants(H, T=0.8):
    """Largest drift over [0, T] of the total momentum (absolute, N.s), of the total energy
    (relative) and of the angular momentum about the origin (relative) of the free pair on an
    undamped Bushing."""
    pair = Pair(True, damping=False)
    J = np.array([1.0, 2.0, 3.0])
    m = 3.0

    def totals():
        P, L, E = np.zeros(3), np.zeros(3), pair.c.get(["energy.stored"])[0]
        for b in pair.body.values():
            o = b.named(STATE)
            r, v, w = (np.array([o[f"{x}[{i}]"] for i in (1, 2, 3)]) for x in "rvw")
            R = quat_matrix(np.array([o[n] for n in ["q.w", "q.x", "q.y", "q.z"]]))
            P += m * v
            L += m * np.cross(r, v) + R @ (J * (R.T @ w))
            E += b.get(["energy.kinetic"])[0]
        return P, L, E

    P0, L0, E0 = totals()
    dP = dL = dE = 0.0
    for _ in range(int(round(T / H))):
        pair.step(H)
        P, L, E = totals()
        dP = max(dP, np.abs(P - P0).max())
        dL = max(dL, np.linalg.norm(L - L0) / np.linalg.norm(L0))
        dE = max(dE, abs(E - E0) / E0)
    pair.close()
    return dP, dL, dE


def test_a_free_pair_keeps_its_momentum_and_its_energy_to_the_coupling_order():
    dP1, dL1, dE1 = invariants(4e-3)
    dP2, dL2, dE2 = invariants(2e-3)
    # momentum: the Bushing's loads balance (f_a + f_b = 0) and no other force acts
    assert max(dP1, dP2) <= 1e-13 * 3.0 * 1.0
    # energy and angular momentum: the Jacobi coupling's first-order drift, halving with H
    for big, small in ((dE1, dE2), (dL1, dL2)):
        assert 1.6 <= big / small <= 2.5, (big, small)
    assert dE2 < 0.05, dE2


def test_a_port_orientation_of_norm_zero_is_refused_at_exit_initialization_naming_the_port():
    log = []
    s = driver.instantiate("Body", driver.unzipped("Body"), instance_name="refused",
                           log=log)
    body = driver.Connector("Body", s)
    body.enter({**{f"port[2].offset.q.{c}": 0.0 for c in "wxyz"}}, {})
    with pytest.raises(Exception):
        s.exitInitializationMode()
    assert any("port[2].offset.q has norm 0" in str(m) for m in log), log
    s.freeInstance()
