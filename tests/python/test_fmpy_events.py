"""Event times against closed forms, through fmpy: FMI 3.0 (FMU3Slave, earlyReturnAllowed) and
FMI 2.0 (FMU2Slave, the outputs event.time / event.count and rollback), SPEC §9, SCENES §3–§5.

The master (tests/python/_events.py) prescribes node b along a closed-form path, sets the exact
inputs at every communication point (also right after an event) and collects the events the FMU
reports: early returns (FMI 3.0) or re-steps to event.time after restoring the state saved before
the step (FMI 2.0, and FMI 3.0 without early return). The FMU locates each event on its own
extrapolation of the inputs over the step, to 1e-10 of the step (src/physics/events.rs,
EVENT_TOL; SPEC §9 asks for 1e-9).

Closed forms (none of them from this project):
- bounce (SCENES §5), mass m at v0 on a penalty stop k, c: contact at t_c = (s − x0)/v0; in
  contact the penetration is (v0/ω_d)·exp(−ζω_n τ)·sin(ω_d τ) (the free response of m ẍ = −k x −
  c ẋ), so it returns to 0 at τ = π/ω_d, ω_d = ω_n sqrt(1 − ζ²). This is the CSLST definition of
  release (the stop status is the sign of the penetration), not the clipped-force one (SCENES §5:
  the never-pulling force vanishes slightly earlier).
- breakaway (SCENES §3): stick spring force k_s·y = c·t reaches μ_s N at t0 = μ_s N / c.
- puck (SCENES §4, friction.coupling = 0): sliding stops at t_v = v0/(μ g), spin at
  t_ω = 3 R ω0 / (4 μ g).

Tolerance: 1e-9 relative on every event time (SPEC §9). Where the extrapolation is exact (the
linear approach, the ramp, velocities extrapolated with their derivatives) the FMU's event is
the true one up to its bracket (≤ 1e-10·H ≤ 1e-12 s, ≤ 5e-11 relative at these times) and
rounding; the release of the bounce is approached by successive events like Newton's method and
ends within the same bracket. The measured errors are printed (pytest -s).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from _events import Path, Twin, relerr, run

REL = 1e-9

STILL_A = {**{f"a.r[{j}]": 0.0 for j in (1, 2, 3)}, **{f"a.v[{j}]": 0.0 for j in (1, 2, 3)},
           **{f"a.w[{j}]": 0.0 for j in (1, 2, 3)}, "a.q.w": 1.0, "a.q.x": 0.0, "a.q.y": 0.0, "a.q.z": 0.0}


def node_b(r=(0.0, 0.0, 0.0), v=(0.0, 0.0, 0.0), alpha=0.0, omega1=0.0):
    """Inputs of node b: position, velocity, rotation by alpha about e1 (= e1 of node a) at rate
    omega1."""
    d = {f"b.r[{j + 1}]": float(r[j]) for j in range(3)}
    d.update({f"b.v[{j + 1}]": float(v[j]) for j in range(3)})
    d.update({"b.w[1]": omega1, "b.w[2]": 0.0, "b.w[3]": 0.0,
              "b.q.w": math.cos(0.5 * alpha), "b.q.x": math.sin(0.5 * alpha), "b.q.y": 0.0, "b.q.z": 0.0})
    return {**STILL_A, **d}


class Bounce(Path):
    """SCENES §5 on ProjectionCartesian: node b approaches the upper stop of CP1 at v0, bounces
    along the free response of the mass on the stop's spring and damper, leaves at the rebound
    velocity."""
    variant = "ProjectionCartesian"
    statuses = ["CSLST1"]

    def __init__(self, zeta, m=1.0, k=2.5e4, s=0.01, x0=-0.0123, v0=1.0):
        self.m, self.k, self.s, self.x0, self.v0, self.zeta = m, k, s, x0, v0, zeta
        self.c = 2.0 * zeta * math.sqrt(k * m)
        self.wn = math.sqrt(k / m)
        self.wd = self.wn * math.sqrt(1.0 - zeta * zeta)
        self.decay = zeta * self.wn
        self.t_contact = (s - x0) / v0
        self.t_release = self.t_contact + math.pi / self.wd
        # the stop force k·p + c·ṗ ∝ (k − c·decay)·sin(ω_d τ) + c·ω_d·cos(ω_d τ) = R·sin(ω_d τ + φ)
        # lets go (is clipped at 0) where ω_d τ + φ = π, before the penetration does
        phi = math.atan2(self.c * self.wd, k - self.c * self.decay)
        self.t_force = self.t_contact + (math.pi - phi) / self.wd
        self.v_out = -v0 * math.exp(-self.decay * math.pi / self.wd)
        self.params = {"stop.upper1": s, "stop.stiffness": k, "stop.damping": self.c}
        self.truth_scale = [s]
        self.t_end = self.t_release + 0.004

    def motion(self, t):
        """(penetration x − s, velocity, acceleration) at t."""
        if t < self.t_contact:
            return self.x0 + self.v0 * t - self.s, self.v0, 0.0
        tau = t - self.t_contact
        if tau <= math.pi / self.wd:
            e, sn, cs = math.exp(-self.decay * tau), math.sin(self.wd * tau), math.cos(self.wd * tau)
            amp = self.v0 / self.wd
            y = amp * e * sn
            v = amp * e * (self.wd * cs - self.decay * sn)
            return y, v, -2.0 * self.decay * v - self.wn ** 2 * y
        return self.v_out * (t - self.t_release), self.v_out, 0.0

    def inputs(self, t):
        y, v, _ = self.motion(t)
        return node_b(r=(self.s + y, 0.0, 0.0), v=(v, 0.0, 0.0))

    def truth(self, t):
        # the penetration of the position the master sends, as the FMU receives it
        return [(self.s + self.motion(t)[0]) - self.s]


class Breakaway(Path):
    """SCENES §3 on Planar: normal preload N, node b pulled along e2 so that the stick spring
    force is c·t."""
    variant = "Planar"
    statuses = ["friction.status"]

    def __init__(self, mu=0.5, N=10.0, ks=1e4, c=37.0):
        self.mu, self.N, self.ks, self.c = mu, N, ks, c
        self.t0 = mu * N / c
        self.params = {"friction.muStatic": mu, "friction.muKinetic": 0.3, "friction.Fint": N,
                       "friction.stickStiffness": ks}
        self.truth_scale = [mu * N]
        self.t_end = self.t0 + 0.02

    def inputs(self, t):
        return node_b(r=(0.0, self.c * t / self.ks, 0.0), v=(0.0, self.c / self.ks, 0.0))

    def truth(self, t):
        return [self.c * t - self.mu * self.N]


class Puck(Path):
    """SCENES §4 (coupling 0) on Planar: normal preloads F_int = m g, M_int = (2/3) R m g, no
    constraint load; node b slides along e2 and spins about e1 with the closed-form decelerations
    μ g and (4/3) μ g / R until each motion stops."""
    variant = "Planar"
    statuses = ["friction.status", "friction.statusR1"]

    def __init__(self, extrapolation=1, mu=0.3, R=0.1, v0=1.0, w0=5.0, m=1.0, g=9.81):
        self.mu, self.R, self.v0, self.w0 = mu, R, v0, w0
        self.acc = (mu * g, 4.0 * mu * g / (3.0 * R))
        self.t_v = v0 / (mu * g)
        self.t_w = 3.0 * R * w0 / (4.0 * mu * g)
        self.params = {"friction.muStatic": mu, "friction.muKinetic": mu, "friction.R": R,
                       "friction.Fint": m * g, "friction.Mint": 2.0 / 3.0 * R * m * g,
                       "friction.coupling": 0, "cosim.extrapolation": extrapolation}
        self.truth_scale = [v0, w0]
        self.t_end = self.t_v + 0.01

    @staticmethod
    def _decelerate(t, rate0, acc, t_stop):
        """(displacement, rate, rate derivative) of a motion at rate0 decelerated by acc until it
        stops at t_stop, at rest afterwards."""
        if t < t_stop:
            return rate0 * t - 0.5 * acc * t * t, rate0 - acc * t, -acc
        return 0.5 * rate0 * t_stop, 0.0, 0.0

    def inputs(self, t):
        y, v, _ = self._decelerate(t, self.v0, self.acc[0], self.t_v)
        alpha, w, _ = self._decelerate(t, self.w0, self.acc[1], self.t_w)
        return node_b(r=(0.0, y, 0.0), v=(0.0, v, 0.0), alpha=alpha, omega1=w)

    def derivatives(self, t):
        return {"b.v[2]": self._decelerate(t, self.v0, self.acc[0], self.t_v)[2],
                "b.w[1]": self._decelerate(t, self.w0, self.acc[1], self.t_w)[2]}

    def truth(self, t):
        # the slip rates, continued past their stop: they change sign at t_v, t_ω
        return [self.acc[0] * t - self.v0, self.acc[1] * t - self.w0]


ROUTES = {"fmi3-early": (3, "early"), "fmi2-rollback": (2, "rollback")}


def drive(route, path, H, record=False):
    version, how = ROUTES[route] if isinstance(route, str) else route
    twin = Twin(version, path.variant, early_return=how == "early")
    try:
        return run(twin, path, H, how, record=record)
    finally:
        twin.free()


def check_route(r, route, H):
    """Item 4 of the brief: at every event the FMU reports event.count ≥ 1; with early return
    event.time is lastSuccessfulTime; with rollback the step's event.time lies inside the step."""
    assert r.events, "no event"
    if ROUTES[route][1] == "early":
        for e in r.events:
            assert e.event_count >= 1, e
            assert e.event_time == e.time, e
        assert r.rollbacks == 0
    else:
        assert r.triggers
        for t, h, ev_time, count in r.triggers:
            assert count >= 1 and t < ev_time <= t + h, (t, h, ev_time, count)
        for e in r.events:
            # the re-step ends at event.time; its own event.time lies in it (the re-step may end
            # a rounding short of the crossing: count 0, the event is then met at the next start)
            assert e.t_start <= e.event_time <= e.time, e


def measured(r, T, H):
    """The time of the last event the master accepted within H of T (the last of a Newton-like
    sequence; a single event where the extrapolation is exact)."""
    cl = r.cluster(T, H)
    assert cl, f"no event within {H} of {T}"
    return cl[-1].time


@pytest.mark.parametrize("route", list(ROUTES))
@pytest.mark.parametrize("H", [1e-3, 5e-3])
@pytest.mark.parametrize("zeta", [0.1, 0.2])
def test_bounce_contact_and_release_times(zeta, H, route):
    """Contact (penetration through 0) and release (penetration back through 0, CSLST1 → 0), each
    located to 1e-9 relative of its closed-form time; between them the damped stop's force lets go
    (k·p + c·ṗ through 0: clipped, it never pulls), an event of its own. The master here iterates
    on the penetration only (its `truth`), so it takes the FMU's first location of the force
    event, on the step's linear extrapolation: that one is checked to lie within the step H of
    its closed-form time."""
    path = Bounce(zeta)
    r = drive(route, path, H)
    check_route(r, route, H)
    # the force letting go changes no CSLST1 (at the stop before and after); the other events
    # are contact and release (the last of a Newton-like sequence on the release)
    force = [e for e in r.events if e.before == (1,) and e.after == (1,)]
    t_c, t_r = measured(r, path.t_contact, H), measured(r, path.t_release, H)
    err_c, err_r = relerr(t_c, path.t_contact), relerr(t_r, path.t_release)
    print(f"bounce zeta={zeta} H={H} {route}: contact {t_c!r} (rel err {err_c:.2e}), release {t_r!r} "
          f"(rel err {err_r:.2e}); release events {len(r.cluster(path.t_release, H))}, force lets go "
          f"at {[e.time for e in force]} (closed form {path.t_force!r}), master rejections "
          f"{r.rejected}, rollbacks {r.rollbacks}, doStep calls {r.steps}")
    assert err_c <= REL and err_r <= REL
    # contact is one event (the approach is linear, so is the extrapolation); every event lies
    # within a step of contact, of the force letting go or of release
    assert len(r.cluster(path.t_contact, H)) == 1
    near = (path.t_contact, path.t_force, path.t_release)
    assert all(min(abs(e.time - T) for T in near) <= H for e in r.events)
    # the force event (CSLST1 stays 1 across it): located on the step's extrapolation (the
    # master iterates on the penetration only), so within that step of its closed-form time
    assert any(abs(e.time - path.t_force) <= H for e in force)
    # CSLST1: free -> at the upper stop -> free
    assert r.status_before(path.t_contact) == (0,) and r.status_after(t_c) == (1,)
    release = [e for e in r.cluster(path.t_release, H) if e not in force]
    assert r.status_before(release[0].time) == (1,) and r.status_after(t_r) == (0,)


def test_bounce_path_is_the_stop_response():
    """The prescribed contact path is the free response of m on this stop: wherever the
    spring-damper force k·p + c·ṗ is positive (the stop does not clip it), the stop force the FMU
    reports is −m ẍ of the path, to 1e-9 of the peak force."""
    path = Bounce(0.2)
    twin = Twin(2, path.variant)
    try:
        twin.start(path.params, path.inputs(0.0))
        t, H, n = 0.0, 5e-4, 0
        peak = path.k * path.v0 / path.wn
        while t < path.t_end:
            twin.set(path.inputs(t))
            y, v, acc = path.motion(t)
            crf1, = twin.real(["CRF1"])
            if y > 0.0 and path.k * y + path.c * v > 0.0:
                assert abs(crf1 - (-path.m * acc)) <= 1e-9 * peak, (t, crf1, -path.m * acc)
                n += 1
            elif y < 0.0 or path.k * y + path.c * v < 0.0:
                assert crf1 == 0.0
            twin.do_step(t, H)
            t += H
        assert n > 20
    finally:
        twin.free()


@pytest.mark.parametrize("route", list(ROUTES))
@pytest.mark.parametrize("H", [1e-3, 3e-3, 7e-3])
def test_breakaway_time(H, route):
    path = Breakaway()
    assert abs(path.t0 / H - round(path.t0 / H)) > 0.01, "H must not divide t0"
    r = drive(route, path, H)
    check_route(r, route, H)
    t0 = measured(r, path.t0, H)
    err = relerr(t0, path.t0)
    print(f"breakaway H={H} {route}: {t0!r} (rel err {err:.2e}), master rejections {r.rejected}")
    assert err <= REL
    assert len(r.events) == 1 and r.rejected == 0
    assert r.status_before(t0) == (1,) and r.status_after(t0) == (2,)   # stick -> slip


@pytest.mark.parametrize("route", list(ROUTES))
@pytest.mark.parametrize("H", [1e-3, 7e-3])
def test_puck_slip_to_stick_times(H, route):
    """cosim.extrapolation = 2 (positions along r + vτ + ½v̇τ², velocities along v + v̇τ). FMI 2.0:
    v̇ of b.v[2] and b.w[1] from fmi2SetRealInputDerivatives (order 1); FMI 3.0: from the velocity
    inputs of the previous communication point, exact for these constant decelerations. The
    slip → stick function (slip rate along the friction force) is then exact over a step."""
    path = Puck(extrapolation=2)
    r = drive(route, path, H)
    check_route(r, route, H)
    t_v, t_w = measured(r, path.t_v, H), measured(r, path.t_w, H)
    err_v, err_w = relerr(t_v, path.t_v), relerr(t_w, path.t_w)
    print(f"puck H={H} {route}: t_v {t_v!r} (rel err {err_v:.2e}), t_w {t_w!r} (rel err {err_w:.2e}), "
          f"master rejections {r.rejected}, events {[e.time for e in r.events]}")
    assert err_v <= REL and err_w <= REL
    assert r.rejected == 0
    # each effect slips until its own event (what it reads afterwards: the test below)
    assert r.status_before(t_w)[1] == 2 and r.status_before(t_v)[0] == 2
    # the other events are the elastic stick springs' breakaways right after the start (the
    # puck starts sticking at t = 0; μ m g / (k_stick v0) ≈ 3e-6 s): nothing else
    others = [e.time for e in r.events if e not in r.cluster(path.t_v, H) + r.cluster(path.t_w, H)]
    assert all(t < 1e-4 for t in others), others


@pytest.mark.parametrize("route", list(ROUTES))
def test_puck_reads_stick_after_each_stop(route):
    """SCENES §4: each motion stops at its time and stays stopped: with the puck at rest after
    both stops, both friction effects must read stick (1) -- the stick springs hold at the
    limit, and on the limit an effect slips only while its slip velocity runs along the force."""
    path = Puck(extrapolation=2)
    r = drive(route, path, 1e-3)
    assert r.statuses[-1][1] == (1, 1), r.statuses[-1]


def bits(records):
    return [(np.float64(t).view(np.uint64), np.asarray(rec, dtype=np.float64).view(np.uint64).tobytes())
            for t, rec in records]


def test_fmi3_without_early_return_equals_the_fmi2_twin():
    """The rollback master on the FMI 3.0 FMU without early return and on its FMI 2.0 twin: the
    same steps and every output after every step, bit for bit (bounce, ζ = 0.1, H = 5 ms)."""
    path = Bounce(0.1)
    r2 = drive((2, "rollback"), path, 5e-3, record=True)
    r3 = drive((3, "rollback"), path, 5e-3, record=True)
    assert r2.rollbacks > 0 and r2.steps == r3.steps
    assert bits(r3.records) == bits(r2.records)
    assert [e.time for e in r3.events] == [e.time for e in r2.events]
