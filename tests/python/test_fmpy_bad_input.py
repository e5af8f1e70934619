"""Bad input gets a clear error and nothing is lost (docs/fmi.md, Bad input), through fmpy's low-level
FMU2Slave API. One test (family) per row:

  non-finite input / parameter           fmi2Error from the setter, log names the variable,
                                         stored value unchanged
  quaternion of norm < 1e-6              refused at fmi2DoStep / fmi2ExitInitializationMode
  negative stiffness, damping, mu, R,    refused at the setter or at fmi2ExitInitializationMode,
  stick stiffness                        message names the parameter
  stop.lower > stop.upper, muK > muS     refused at fmi2ExitInitializationMode (or at the setter
                                         after initialization), message names both
  fixed parameter after initialization   fmi2Error, message
  unknown value reference, wrong type    fmi2Error, message
  flexion alpha -> pi                    fmi2DoStep returns fmi2Error (or fmi2Discard), message
                                         about the singular configuration; fmi2Reset or
                                         fmi2SetFMUstate recovers

fmi2Instantiate's refusals (wrong GUID, fmuType ModelExchange, empty or NULL instance name) are
tested through the C ABI in tests/abi_lifecycle.rs (instantiate_refuses_bad_arguments_after_logging).

"Nothing is lost" is checked every time: after the refusal the instance reports exactly the
values it had (bitwise), and going on with good input gives, bit for bit, the run of an
instance that never saw the bad input.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

import _ref
from conftest import VARIANTS, Connector, vr

fmi2Discard, fmi2Error = 2, 3
fmi2LastSuccessfulTime = 2
NAN, INF = float("nan"), float("inf")
H = 0.01


# ==========================================================================
# driver
# ==========================================================================


class Conn(Connector):
    """conftest's Connector (scripts/cosim/driver.py) with the record this file compares (every
    output, parameter and input), driven along `motion_inputs`, and the instance's log."""

    def __init__(self, variant, slave, log):
        super().__init__(variant, slave)
        self.log = log

    def record(self):
        return (
            tuple(self.s.getReal(self.real_out)),
            tuple(self.s.getInteger(self.int_out)),
            self.values(),
        )

    def drive(self, n, h=H):
        return super().drive(lambda t: motion_inputs(self.variant, t), n, h)

    def step(self, h=H):
        super().step(h)

    def errors_since(self, n):
        return [m for (status, _cat, m) in self.log[n:] if status >= fmi2Discard]


@pytest.fixture
def conn(make_slave):
    count = [0]

    def make(variant):
        count[0] += 1
        log = []
        return Conn(variant, make_slave(variant, instance_name=f"bad-{variant}-{count[0]}", log=log), log)

    return make


def refused(c, fn, *args, names=(), status=(fmi2Error,), **kw):
    """Calls fn, expects an FMICallException with one of the statuses and one new log message
    (non-OK) that contains every string in names. Returns that message."""
    n = len(c.log)
    with pytest.raises(FMICallException) as e:
        fn(*args, **kw)
    assert e.value.status in status, (e.value.function, e.value.status)
    msgs = c.errors_since(n)
    assert msgs, f"{e.value.function} failed without a log message"
    for nm in names:
        assert any(nm in m for m in msgs), (nm, msgs)
    return msgs[-1]


# a simple motion for every variant: node a fixed, node b translating and turning a little
QA = _ref.quat_exp([0.3, -0.2, 0.5])
RA = _ref.quat_to_matrix(QA)


def motion_pose(variant, t):
    if variant == "Planar":
        rel = np.array([0.1, 0.2 + 0.01 * math.sin(3 * t), -0.1 + 0.005 * math.sin(2 * t)])
        return {
            "a.r": np.array([0.1, 0.2, -0.3]), "a.q": QA,
            "b.r": np.array([0.1, 0.2, -0.3]) + RA @ rel,
            "b.q": _ref.quat_mul(QA, _ref.quat_exp([0.3 + 0.05 * math.sin(2 * t), 0.0, 0.0])),
            "b.v": RA @ np.array([0.0, 0.03 * math.cos(3 * t), 0.01 * math.cos(2 * t)]),
            "b.w": 0.1 * math.cos(2 * t) * RA[:, 0],
        }
    return {
        "a.r": np.array([0.1, 0.2, -0.3]), "a.q": QA,
        "b.r": np.array([0.5, 0.5, 0.3]) + 0.05 * np.array([math.sin(3 * t), math.cos(2 * t), 0.0]),
        "b.q": _ref.quat_mul(_ref.quat_exp([0.2 * math.sin(2 * t), 0.1, 0.2]), QA),
        "b.v": 0.05 * np.array([3 * math.cos(3 * t), -2 * math.sin(2 * t), 0.0]),
        "b.w": np.array([0.4 * math.cos(2 * t), 0.0, 0.0]),
    }


def motion_inputs(variant, t):
    return _ref.pose_to_inputs(variant, motion_pose(variant, t))


def base_params(variant):
    p = {}
    for _name, k in _ref.components_of(variant):
        p[f"elasticity.k{k}"] = 1000.0 if k <= 3 else 50.0
        p[f"damping.c{k}"] = 10.0 if k <= 3 else 0.5
    if variant == "Planar":
        p.update({"friction.muStatic": 0.4, "friction.muKinetic": 0.3, "friction.Fint": 100.0,
                  "friction.Mint": 2.0, "friction.R": 0.05, "friction.stickStiffness": 1.0e4})
    return p


def clean_run(conn, variant, n_before, n_after, params=None):
    """Records of an instance that never sees bad input: n_before steps, then n_after."""
    c = conn(variant).start(params or base_params(variant), motion_inputs(variant, 0.0))
    c.drive(n_before)
    return c.drive(n_after)


def first_component(variant):
    return _ref.components_of(variant)[0][1]


# ==========================================================================
# non-finite values
# ==========================================================================

# stop bounds are +-INF when absent and friction.maxForce is +INF when uncapped: only NaN is
# non-finite garbage for those.
INF_ALLOWED = ("stop.lower", "stop.upper", "friction.maxForce")


def _bad_values(name):
    if name.startswith(INF_ALLOWED):
        return [NAN]
    return [NAN, INF, -INF]


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("phase", ["initialization", "after initialization"])
def test_nonfinite_value_refused(conn, variant, phase):
    c = conn(variant)
    params, inputs = base_params(variant), motion_inputs(variant, 0.0)
    c.enter(params, inputs)
    if phase == "after initialization":
        c.s.exitInitializationMode()
        c.drive(3)
    before = c.values()
    targets = c.real_in + [r for r in c.params if r.type == "Real"]
    for r in targets:
        for bad in _bad_values(r.name):
            old = c.s.getReal([r])[0]
            refused(c, c.s.setReal, [r], [bad], names=[r.name])
            new = c.s.getReal([r])[0]
            assert new == old or (math.isnan(old) and math.isnan(new)), (r.name, bad, old, new)
    # a non-finite input derivative is refused too, naming the input
    for r in c.real_in:
        refused(c, c.s.setRealInputDerivatives, [r], [1], [NAN], names=[r.name])
    assert c.values() == before
    if phase == "initialization":
        c.s.exitInitializationMode()
        c.drive(3)
    # nothing lost: the run goes on exactly like one that never saw the bad values (which also
    # shows the refused input derivatives were not stored)
    assert c.drive(20) == clean_run(conn, variant, 3, 20)


@pytest.mark.parametrize("variant", VARIANTS)
def test_input_derivative_of_an_acceleration_refused(conn, variant):
    """The acceleration inputs (a.dv, a.dw, b.dv, b.dw) are themselves derivatives: a finite
    fmi2SetRealInputDerivatives on one is refused with a message naming it, in the same call as
    a valid one, and nothing is stored (all or nothing): the run goes on like a clean one."""
    c = conn(variant).start(base_params(variant), motion_inputs(variant, 0.0))
    c.drive(3)
    before = c.values()
    acc = [r for r in c.real_in if r.name[1:4] in (".dv", ".dw")]
    assert acc, "every variant has acceleration inputs"
    pose = [r for r in c.real_in if r not in acc][0]
    for r in acc:
        refused(c, c.s.setRealInputDerivatives, [pose, r], [1, 1], [1.0, 2.0],
                names=[r.name, "takes no input derivative"])
    assert c.values() == before
    assert c.drive(20) == clean_run(conn, variant, 3, 20)


# ==========================================================================
# degenerate quaternion
# ==========================================================================


def _nodes_with_q(variant):
    return [n for n in ("a", "b") if "q" in _ref.VARIANTS[variant][n]]


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("scale", [0.0, 1e-7, 9e-7])
def test_tiny_quaternion_refused_at_step(conn, variant, scale):
    """A quaternion of norm `scale` < 1e-6 (components may be set one by one, so the setter
    accepts it): fmi2DoStep refuses it with a message naming the orientation; then the master
    corrects it and the step goes on exactly as if nothing happened."""
    for node in _nodes_with_q(variant):
        c = conn(variant).start(base_params(variant), motion_inputs(variant, 0.0))
        c.drive(5)
        good = motion_inputs(variant, c.t)
        c.set(good)
        before_vals = c.values()
        q = np.array([good[f"{node}.q.{k}"] for k in "wxyz"]) * scale
        c.s.setReal([c.v[f"{node}.q.{k}"] for k in "wxyz"], list(q))
        t0 = c.t
        msg = refused(c, c.step, names=[f"{node}.q"])
        assert "norm" in msg or "rotation" in msg, msg
        assert c.t == t0 and c.s.getRealStatus(fmi2LastSuccessfulTime) == t0
        # correct the orientation and retry the same step: the run is the clean one (whose
        # 6th step starts from exactly these inputs)
        c.set(good)
        assert c.values() == before_vals
        c.step()
        assert c.drive(20) == clean_run(conn, variant, 6, 20)


@pytest.mark.parametrize("variant", VARIANTS)
def test_tiny_quaternion_refused_in_initialization(conn, variant):
    for node in _nodes_with_q(variant):
        c = conn(variant)
        inputs = motion_inputs(variant, 0.0)
        c.enter(base_params(variant), inputs)
        c.s.setReal([c.v[f"{node}.q.{k}"] for k in "wxyz"], [1e-7, 0.0, 0.0, 0.0])
        refused(c, c.s.exitInitializationMode, names=[f"{node}.q"])
        # the master corrects the orientation: initialization completes and the run is the
        # clean one
        c.set(inputs)
        c.s.exitInitializationMode()
        assert c.drive(20) == clean_run(conn, variant, 0, 20)


@pytest.mark.parametrize("variant", VARIANTS)
def test_small_but_valid_quaternion_is_normalised(conn, variant):
    """Norm 1e-5 (above the 1e-6 limit) is a valid orientation: the FMU normalises it, so the
    outputs equal those of the unit quaternion to round-off (relative 1e-12: normalising is a
    few flops, scaling by 1e-5 is exact up to one rounding per component)."""
    c = conn(variant).start(base_params(variant), motion_inputs(variant, 0.0))
    c.drive(3)
    good = motion_inputs(variant, c.t)
    c.set(good)
    y_unit = np.array(c.s.getReal(c.real_out))
    for node in _nodes_with_q(variant):
        small = dict(good)
        for k in "wxyz":
            small[f"{node}.q.{k}"] = good[f"{node}.q.{k}"] * 1e-5
        c.set(small)
        y = np.array(c.s.getReal(c.real_out))
        scale = float(np.max(np.abs(y_unit)))
        assert np.max(np.abs(y - y_unit)) <= 1e-12 * scale, node
        c.set(good)


# ==========================================================================
# negative stiffness, damping, mu, R, stick stiffness
# ==========================================================================


def _nonneg_params(variant):
    names = []
    for _n, k in _ref.components_of(variant):
        names += [f"elasticity.k{k}", f"damping.c{k}"]
    spec = _ref.VARIANTS[variant]
    if spec["trans"]:
        names += ["stop.stiffness", "stop.damping"]
    if spec["rot"]:
        names += ["stop.rotStiffness", "stop.rotDamping"]
    if variant == "Planar":
        names += ["constraint.stiffness", "constraint.damping", "constraint.rotStiffness",
                  "constraint.rotDamping", "friction.muStatic", "friction.muKinetic", "friction.R",
                  "friction.stickStiffness", "friction.stickStiffnessR1", "friction.stickDamping",
                  "friction.stickDampingR1"]
    return names


NONNEG = [(v, p) for v in VARIANTS for p in _nonneg_params(v)]


@pytest.mark.parametrize("variant,param", NONNEG, ids=[f"{v}-{p}" for v, p in NONNEG])
def test_negative_parameter_refused(conn, variant, param):
    params = base_params(variant)
    # initialization: refused by the setter, or at fmi2ExitInitializationMode
    c = conn(variant)
    c.enter(params, motion_inputs(variant, 0.0))
    old = c.value(param)
    n = len(c.log)
    try:
        c.s.setReal([c.v[param]], [-1.0])
        at_set = False
    except FMICallException as e:
        assert e.status == fmi2Error
        assert any(param in m for m in c.errors_since(n)), c.errors_since(n)
        assert c.value(param) == old
        at_set = True
    if not at_set:
        refused(c, c.s.exitInitializationMode, names=[param])
        c.set({param: old})
    c.s.exitInitializationMode()
    assert c.drive(10) == clean_run(conn, variant, 0, 10)

    # after initialization only the setter can refuse
    c = conn(variant).start(params, motion_inputs(variant, 0.0))
    c.drive(3)
    before = c.values()
    refused(c, c.s.setReal, [c.v[param]], [-1.0], names=[param])
    assert c.values() == before
    assert c.drive(10) == clean_run(conn, variant, 3, 10)


# ==========================================================================
# inconsistent pairs: stop.lower > stop.upper, muKinetic > muStatic
# ==========================================================================


def _pairs(variant):
    k = first_component(variant)
    out = [(f"stop.lower{k}", 0.5, f"stop.upper{k}", 0.1)]
    if variant == "Planar":
        out.append(("friction.muKinetic", 0.5, "friction.muStatic", 0.4))
    return out


PAIRS = [(v,) + p for v in VARIANTS for p in _pairs(v)]


@pytest.mark.parametrize("variant,big,big_val,small,small_val", PAIRS,
                         ids=[f"{p[0]}-{p[1]}>{p[3]}" for p in PAIRS])
def test_inconsistent_pair_refused(conn, variant, big, big_val, small, small_val):
    params = base_params(variant)
    # initialization: both set (a setter cannot judge a pair while the other half is still to
    # come), refused at fmi2ExitInitializationMode naming both
    c = conn(variant)
    c.enter(params, motion_inputs(variant, 0.0))
    old_big = c.value(big)
    c.set({small: small_val, big: big_val})
    refused(c, c.s.exitInitializationMode, names=[big, small])
    c.set({big: old_big, small: params.get(small, c.value(small))})
    c.s.exitInitializationMode()

    # after initialization: the setter refuses the value that breaks the pair, naming both
    params2 = dict(params, **{small: small_val})
    c = conn(variant).start(params2, motion_inputs(variant, 0.0))
    c.drive(3)
    before = c.values()
    refused(c, c.s.setReal, [c.v[big]], [big_val], names=[big, small])
    assert c.values() == before
    assert c.drive(10) == clean_run(conn, variant, 3, 10, params2)


# ==========================================================================
# fixed parameters after initialization
# ==========================================================================


def _fixed(variant):
    k = first_component(variant)
    out = [(f"reference.value{k}", 0.123), (f"reference.given{k}", True)]
    if variant == "Planar":
        out.append(("friction.coupling", 1))
    return out


FIXED = [(v,) + f for v in VARIANTS for f in _fixed(v)]


@pytest.mark.parametrize("variant,name,value", FIXED, ids=[f"{v}-{n}" for v, n, _ in FIXED])
def test_fixed_parameter_after_initialization(conn, variant, name, value):
    assert vr(variant)[name].variability == "fixed"
    params = base_params(variant)
    # positive control: in initialization it can be set and read back
    c0 = conn(variant)
    c0.enter(params, motion_inputs(variant, 0.0))
    c0.set({name: value})
    assert c0.value(name) == value
    # after initialization: refused, value unchanged, run unaffected
    c = conn(variant).start(params, motion_inputs(variant, 0.0))
    c.drive(3)
    before = c.values()
    r = c.v[name]
    setter = {"Real": c.s.setReal, "Integer": c.s.setInteger, "Boolean": c.s.setBoolean}[r.type]
    refused(c, setter, [r], [value], names=[name])
    assert c.values() == before
    assert c.drive(10) == clean_run(conn, variant, 3, 10)


# ==========================================================================
# unknown value reference, wrong type
# ==========================================================================


@pytest.mark.parametrize("variant", VARIANTS)
def test_unknown_value_reference(conn, variant):
    c = conn(variant).start(base_params(variant), motion_inputs(variant, 0.0))
    c.drive(3)
    before = c.record()
    bad = max(vr(variant).values()) + 1000
    # a VR that belongs to another variant only (VRs are stable across variants)
    others = {int(r) for v in VARIANTS for r in vr(v).values()} - {int(r) for r in vr(variant).values()}
    for b in [bad] + sorted(others)[:3]:
        refused(c, c.s.setReal, [b], [1.0], names=[str(b)])
        refused(c, c.s.getReal, [b], names=[str(b)])
        refused(c, c.s.setInteger, [b], [1], names=[str(b)])
        refused(c, c.s.getInteger, [b], names=[str(b)])
        refused(c, c.s.setBoolean, [b], [True], names=[str(b)])
        refused(c, c.s.getBoolean, [b], names=[str(b)])
        refused(c, c.s.getDirectionalDerivative, [c.real_out[0]], [b], [1.0], names=[str(b)])
    assert c.record() == before
    assert c.drive(10) == clean_run(conn, variant, 3, 10)


@pytest.mark.parametrize("variant", VARIANTS)
def test_wrong_type(conn, variant):
    c = conn(variant).start(base_params(variant), motion_inputs(variant, 0.0))
    c.drive(3)
    before = c.record()
    k = first_component(variant)
    real_par, int_par, bool_par = c.v[f"elasticity.k{k}"], c.v["cosim.extrapolation"], c.v[f"reference.given{k}"]
    int_out = c.v[f"CSLST{k}"]
    real_out = c.real_out[0]
    real_in = c.real_in[0]
    cases = [
        (c.s.setInteger, [real_par], [5], real_par),
        (c.s.setBoolean, [real_par], [True], real_par),
        (c.s.setInteger, [real_in], [1], real_in),
        (c.s.setReal, [int_par], [0.0], int_par),
        (c.s.setBoolean, [int_par], [False], int_par),
        (c.s.setReal, [bool_par], [1.0], bool_par),
        (c.s.getInteger, [real_out], None, real_out),
        (c.s.getReal, [int_out], None, int_out),
        (c.s.getBoolean, [real_par], None, real_par),
        # wrong causality: an output cannot be set
        (c.s.setReal, [real_out], [1.0], real_out),
    ]
    for fn, vrs, vals, r in cases:
        args = (vrs,) if vals is None else (vrs, vals)
        refused(c, fn, *args, names=[r.name])
    assert c.record() == before
    assert c.drive(10) == clean_run(conn, variant, 3, 10)


# ==========================================================================
# singular configurations during a step
# ==========================================================================

SINGULAR = [
    # (variant, label, node b relative rotation (rotation vector in a's frame), w_b (in a's frame), h)
    # 3.14159 rad is 2.65e-6 rad short of pi: there the centred-triad gradients, hence the node
    # moments, are ~1/(pi - alpha) ~ 4e5 times the connector moments (the brief's example of a
    # configuration to refuse)
    ("ProjectionFlexionTorsion", "alpha = pi", [math.pi, 0.0, 0.0], [0.0, 0.0, 0.0], H),
    ("Bushing", "alpha = pi", [math.pi, 0.0, 0.0], [0.0, 0.0, 0.0], H),
    ("ProjectionFlexionTorsion", "alpha = 3.14159", [3.14159, 0.0, 0.0], [0.0, 0.0, 0.0], H),
    ("Bushing", "alpha = 3.14159 about y", [0.0, 3.14159, 0.0], [0.0, 0.0, 0.0], H),
    # linear extrapolation over the step carries alpha from 3.05 through pi (at tau ~ 0.09 s) to
    # 2 pi - 3.25 = 3.03 rad: both ends are regular, the path is not
    ("ProjectionFlexionTorsion", "path through pi", [3.05, 0.0, 0.0], [1.0, 0.0, 0.0], 0.2),
    ("Bushing", "path through pi", [3.05, 0.0, 0.0], [1.0, 0.0, 0.0], 0.2),
    # PLANAR: e3b perpendicular to a's 2-3 plane, the rotation alpha is undefined
    ("Planar", "revolute undefined", [0.0, math.pi / 2, 0.0], [0.0, 0.0, 0.0], H),
]


def _singular_inputs(variant, rotvec, w, t):
    pose = motion_pose(variant, t)
    pose["b.q"] = _ref.quat_mul(QA, _ref.quat_exp(rotvec))
    pose["b.w"] = RA @ np.array(w)
    pose["b.v"] = np.zeros(3)
    return _ref.pose_to_inputs(variant, pose)


@pytest.mark.parametrize("variant,label,rotvec,w,h", SINGULAR, ids=[f"{s[0]}-{s[1]}" for s in SINGULAR])
def test_singular_configuration_step_refused_and_recoverable(conn, variant, label, rotvec, w, h):
    params = base_params(variant)
    c = conn(variant).start(params, motion_inputs(variant, 0.0))
    c.drive(5)
    t_good = c.t
    saved = c.s.getFMUstate()
    saved_record = c.record()

    c.set(_singular_inputs(variant, rotvec, w, c.t))
    n = len(c.log)
    with pytest.raises(FMICallException) as e:
        c.s.doStep(currentCommunicationPoint=c.t, communicationStepSize=h)
    assert e.value.status in (fmi2Discard, fmi2Error), e.value.status
    msgs = c.errors_since(n)
    # the flexion cases name the singular configuration; PLANAR says its rotation is undefined
    assert msgs and any("singular" in m.lower() or "undefined" in m.lower() for m in msgs), msgs
    if e.value.status == fmi2Discard:
        lst = c.s.getRealStatus(fmi2LastSuccessfulTime)
        assert t_good <= lst < t_good + h

    # recovery 1: fmi2SetFMUstate to the last good state, then the run goes on exactly like a
    # run that never saw the singular input
    c.s.setFMUstate(saved)
    c.s.freeFMUstate(saved)
    c.t = t_good
    # parameters, inputs and time exactly as saved; Real outputs to round-off (1e-12 of the
    # largest). Whether ALL outputs (Real and Integer) right after a restore equal bit for bit
    # those at the save point is tested, strictly, in
    # test_fmpy_rollback.py::test_restored_state_reports_the_saved_values; here the point is that
    # the last good state is kept and recovers.
    assert c.values() == saved_record[2]
    assert c.s.getRealStatus(fmi2LastSuccessfulTime) == t_good
    y_saved, y_now = np.array(saved_record[0]), np.array(c.s.getReal(c.real_out))
    assert np.max(np.abs(y_now - y_saved)) <= 1e-12 * np.max(np.abs(y_saved))
    # and the run goes on bit for bit like one that never saw the singular input
    assert c.drive(20) == clean_run(conn, variant, 5, 20)

    # recovery 2: fmi2Reset, a new experiment: the same as a fresh instance
    c.set(_singular_inputs(variant, rotvec, w, c.t))
    with pytest.raises(FMICallException):
        c.s.doStep(currentCommunicationPoint=c.t, communicationStepSize=h)
    c.s.reset()
    c.start(params, motion_inputs(variant, 0.0))
    assert c.drive(25) == clean_run(conn, variant, 0, 25)
