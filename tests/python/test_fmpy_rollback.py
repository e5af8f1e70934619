"""Rollback with fmi2GetFMUstate / fmi2SetFMUstate through fmpy's FMU2Slave (docs/fmi.md): the
repeated runs equal the first bit for bit (Planar friction in stick and slip, with stick dampers,
every variant), a restored state reads the saved values, serialized states restored into a fresh
instance continue identically, corrupt / truncated / foreign serialized states are refused and
leave the instance unchanged, and the serialized size (reported) is at most 1024 bytes.

Uses conftest's `conn` fixture and _cosim_helpers (scenario, H_ROLL)."""

from __future__ import annotations

import pytest
from fmpy.fmi1 import FMICallException

from _cosim_helpers import H_ROLL, scenario
from conftest import VARIANTS

N_ROLL = 100


def _survey_planar(conn):
    """Runs the Planar friction scenario once; returns the statuses after every step."""
    params, inputs_at = scenario("Planar")
    c = conn("Planar").start(params, inputs_at(0.0))
    status, status_r1, stop = [], [], []
    for _ in range(400):
        c.set(inputs_at(c.t))
        c.step(H_ROLL)
        status.append(c.value("friction.status"))
        status_r1.append(c.value("friction.statusR1"))
        stop.append(c.value("CSLST2"))
    return status, status_r1, stop


def _rollback_check(c, inputs_at, n_before):
    """Runs n_before steps, saves the state, records N_ROLL steps, restores, repeats (twice),
    asserts the repeated runs equal the first bit for bit, and returns (record at the save point,
    records right after each restore, first run, state handle, save time)."""
    c.drive(inputs_at, n_before, H_ROLL, record=False)
    t_save = c.t
    before = c.record()
    state = c.s.getFMUstate()
    first = c.drive(inputs_at, N_ROLL, H_ROLL)
    restored = []
    for _ in range(2):  # restoring twice must give the same run twice
        c.s.setFMUstate(state)
        c.t = t_save
        restored.append(c.record())
        again = c.drive(inputs_at, N_ROLL, H_ROLL)
        # bit for bit: == on every float, no tolerance (docs/fmi.md)
        assert again == first
    return before, restored, first, state, t_save


def _record_diff(c, a, b):
    """Names and values where two records differ (for failure messages)."""
    names = [[r.name for r in c.real_out], [r.name for r in c.int_out], [r.name for r in c.real_in], ["time"]]
    out = {}
    for grp, (x, y) in enumerate(zip(a, b)):
        if grp == 3:
            x, y = (x,), (y,)
        for n, u, w in zip(names[grp], x, y):
            if u != w:
                out[n] = (u, w)
    return out


def _fresh_restore(conn, variant, data, t_save):
    """A FRESH instance (instantiate, setupExperiment, enter/exit initialization with default
    values), then fmi2DeSerializeFMUstate + fmi2SetFMUstate."""
    fresh = conn(variant)
    fresh.s.setupExperiment(startTime=0.0)
    fresh.s.enterInitializationMode()
    fresh.s.exitInitializationMode()
    st2 = fresh.s.deSerializeFMUstate(data)
    fresh.s.setFMUstate(st2)
    fresh.s.freeFMUstate(st2)
    fresh.t = t_save
    return fresh


@pytest.mark.parametrize("phase", ["stick", "slip"])
def test_rollback_planar_friction_bitwise(conn, phase):
    status, status_r1, stop = _survey_planar(conn)
    # the scenario really has both friction phases and the stop engaged (else the test is void)
    assert 1 in status and 2 in status, status
    assert 1 in status_r1 and 2 in status_r1, status_r1
    assert 1 in stop, "the stop on u2 is never reached"
    want = 1 if phase == "stick" else 2
    i_save = next(i for i in range(60, len(status) - N_ROLL) if status[i] == want)
    params, inputs_at = scenario("Planar")

    c = conn("Planar").start(params, inputs_at(0.0))
    before, _restored, first, state, t_save = _rollback_check(c, inputs_at, i_save + 1)
    # saved mid-run in the wanted phase (status after step i_save); the recorded window sees
    # stick/slip transitions (and, from the stick save, the stop)
    statuses = [r[1][c.int_out.index(c.v["friction.status"])] for r in first]
    stops = [r[1][c.int_out.index(c.v["CSLST2"])] for r in first]
    assert before[1][c.int_out.index(c.v["friction.status"])] == want
    assert len(set(statuses)) >= 2, statuses
    assert 1 in stops or phase == "slip", stops

    # serialized state into a FRESH instance continues identically
    data = c.s.serializeFMUstate(state)
    assert isinstance(data, bytes) and len(data) <= 1024, len(data)
    c.s.freeFMUstate(state)
    fresh = _fresh_restore(conn, "Planar", data, t_save)
    assert fresh.drive(inputs_at, N_ROLL, H_ROLL) == first


@pytest.mark.parametrize("coupling", [0, 1])
def test_rollback_planar_stick_dampers_bitwise(conn, coupling):
    """The same rollback and serialization checks with stick dampers, whose elastic slip and
    plastic slip rate are part of the FMU state, uncoupled and coupled. Uncoupled: saved in
    stick, the recorded window also slips (found by a survey run). Coupled: on this path the
    spin keeps the coupled limit slipping through the reversals, so the window is all slip."""
    params, inputs_at = scenario("Planar")
    params.update({"friction.coupling": coupling, "friction.stickDamping": 200.0,
                   "friction.stickDampingR1": 0.5})
    survey = conn("Planar").start(params, inputs_at(0.0))
    status = [r[1][survey.int_out.index(survey.v["friction.status"])]
              for r in survey.drive(inputs_at, 400, H_ROLL)]
    want = {1, 2} if coupling == 0 else {2}
    i_save = next(i for i in range(20, len(status) - N_ROLL)
                  if status[i] == min(want) and set(status[i + 1:i + 1 + N_ROLL]) == want)
    c = conn("Planar").start(params, inputs_at(0.0))
    _before, _restored, first, state, t_save = _rollback_check(c, inputs_at, i_save + 1)
    assert {r[1][c.int_out.index(c.v["friction.status"])] for r in first} == want
    data = c.s.serializeFMUstate(state)
    assert len(data) <= 1024, len(data)
    c.s.freeFMUstate(state)
    assert _fresh_restore(conn, "Planar", data, t_save).drive(inputs_at, N_ROLL, H_ROLL) == first


@pytest.mark.parametrize("variant", VARIANTS)
def test_restored_state_reports_the_saved_values(conn, variant):
    """Right after fmi2SetFMUstate (same instance, or a fresh one from the serialized bytes)
    every output, input and the time read exactly what they read when fmi2GetFMUstate was
    called (the FMU state is the whole observable state of the slave; a master that rolls back
    and re-reads the outputs must see the same values). Saved mid-run right after a step (the
    common case: save at a communication point, step, reject, restore)."""
    params, inputs_at = scenario(variant)
    c = conn(variant).start(params, inputs_at(0.0))
    diffs = {}
    for n in range(1, 81):
        c.set(inputs_at(c.t))
        c.step(H_ROLL)
        if n % 4:
            continue
        before = c.record()
        state = c.s.getFMUstate()
        c.s.setFMUstate(state)
        d_same = _record_diff(c, before, c.record())
        data = c.s.serializeFMUstate(state)
        c.s.freeFMUstate(state)
        fresh = _fresh_restore(conn, variant, data, c.t)
        d_fresh = _record_diff(fresh, before, fresh.record())
        if d_same or d_fresh:
            diffs[f"after step {n}"] = {"same instance": d_same, "fresh instance": d_fresh}
    assert not diffs, f"{len(diffs)} of 20 save points differ; first: {next(iter(diffs.items()))}"


def _corruptions(data, foreign):
    """(label, bytes) of corrupt versions of a serialized state."""
    out = []
    for i in range(len(data)):
        for mask in (0x01, 0x80, 0xFF):  # lowest bit, highest bit, whole byte
            b = bytearray(data)
            b[i] ^= mask
            out.append((f"byte {i} ^ {mask:#04x}", bytes(b)))
    for n in sorted({0, 1, 4, 8, len(data) // 2, len(data) - 9, len(data) - 8, len(data) - 1}):
        out.append((f"truncated to {n} bytes", data[:n]))
    out.append(("one byte appended", data + b"\x00"))
    out.append(("8 bytes appended", data + bytes(8)))
    for v, other in foreign.items():
        out.append((f"state of {v}", other))
    return out


def test_corrupt_serialized_state_refused_instance_unchanged(conn):
    params, inputs_at = scenario("Planar")
    # a foreign state of every other variant (after a few steps of its own scenario)
    foreign = {}
    for v in VARIANTS:
        if v == "Planar":
            continue
        p, f = scenario(v)
        o = conn(v).start(p, f(0.0))
        o.drive(f, 5, H_ROLL, record=False)
        st = o.s.getFMUstate()
        foreign[v] = o.s.serializeFMUstate(st)
        o.s.freeFMUstate(st)

    log = []
    c = conn("Planar", log=log)
    c.start(params, inputs_at(0.0))
    c.drive(inputs_at, 150, H_ROLL, record=False)
    st = c.s.getFMUstate()
    data = c.s.serializeFMUstate(st)
    c.s.freeFMUstate(st)
    t0 = c.t
    before = c.record()

    accepted = []
    for label, bad in _corruptions(data, foreign):
        n_log = len(log)
        try:
            st_bad = c.s.deSerializeFMUstate(bad)
        except FMICallException as e:
            assert e.status == 3, (label, e.status)  # fmi2Error
            msgs = [m for (s, _cat, m) in log[n_log:] if s >= 3]
            assert msgs and "fmi2DeSerializeFMUstate" in msgs[-1], (label, log[n_log:])
            continue
        c.s.freeFMUstate(st_bad)
        accepted.append(label)
    assert not accepted, f"corrupt serialized states accepted: {accepted[:20]} ({len(accepted)} in all)"

    # instance unchanged: every output, input and the time are as before, and the run goes on
    # exactly as from the good state restored in a fresh instance
    assert c.record() == before
    cont = c.drive(inputs_at, 50, H_ROLL)
    fresh = _fresh_restore(conn, "Planar", data, t0)
    assert fresh.drive(inputs_at, 50, H_ROLL) == cont


SERIALIZED_SIZES = {}


@pytest.mark.parametrize("variant", VARIANTS)
def test_serialized_state_every_variant(conn, variant, record_property, capsys):
    """Rollback and fresh-instance restore for every variant (springs, dampers, a stop);
    serialized size <= 1024 bytes (reported)."""
    params, inputs_at = scenario(variant)
    c = conn(variant).start(params, inputs_at(0.0))
    before, _restored, first, state, t_save = _rollback_check(c, inputs_at, 37)
    data = c.s.serializeFMUstate(state)
    # serializing the same state twice gives the same bytes
    assert c.s.serializeFMUstate(state) == data
    c.s.freeFMUstate(state)
    SERIALIZED_SIZES[variant] = len(data)
    record_property("serialized_size", len(data))
    with capsys.disabled():
        print(f"\n[serialized FMU state] {variant}: {len(data)} bytes")
    assert len(data) <= 1024, f"{variant}: serialized state is {len(data)} bytes"
    fresh = _fresh_restore(conn, variant, data, t_save)
    assert fresh.drive(inputs_at, N_ROLL, H_ROLL) == first
