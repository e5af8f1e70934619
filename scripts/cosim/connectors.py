"""The connector FMU as the co-simulation master drives it: one instance (FMI 2.0 through fmpy's
FMU2Slave, or FMI 3.0 through FMU3Slave with early return), initialised, with every per-step
call prepared once: ctypes buffers for the inputs the master writes, the outputs it reads, the
input derivatives and acceleration inputs, directional-derivative seeds, the FMU state. A step
builds no value-reference lists or ctypes arrays (fmpy's convenience getReal/setReal would).

Loading, instantiating, initialising and name-based access are the shared driver's
(scripts/cosim/driver.py, also the fmpy tests' driver). Uses driver only; the bodies, the
coupling methods and the master's loop use this.
"""
from __future__ import annotations

import ctypes
import os
from pathlib import Path

import numpy as np
from fmpy.fmi2 import fmi2FMUstate, fmi2Integer, fmi2Real, fmi2ValueReference
from fmpy.fmi3 import FMU3Slave, fmi3Boolean, fmi3Float64, fmi3ValueReference

from . import driver

REPO = Path(__file__).resolve().parents[2]
DIST = Path(os.environ.get("COSIM_DIST", REPO / "dist"))     # the FMUs (default: dist/)
FMI3 = "fmi3"                     # the FMI 3.0 FMUs are DIST/fmi3/<variant>.fmu


class CosimFailure(RuntimeError):
    """A run that cannot go on: the FMU refused a step, the state blew up, rollback diverged."""


def model_description(variant):
    try:
        return driver.model_description(variant, DIST)
    except driver.MissingFMU as e:
        raise SystemExit(f"error: {e.path} is missing; run ./scripts/run first") from None


def unzipped(variant, unzipdir=None):
    if unzipdir is not None:
        return str(unzipdir)
    model_description(variant)
    return driver.unzipped(variant, DIST)


class Connector(driver.Connector):
    """One connector FMU instance (scripts/cosim/driver.py), initialised, with every per-step
    call prepared once.

    `in_names`: the inputs the master writes each step (buffer `x`, derivatives `d`);
    `out_names`: the outputs it reads each step (buffer `y`)."""

    _count = 0
    version = 2

    def __init__(self, variant, params, init_inputs, in_names, out_names, unzipdir=None,
                 acc_names=()):
        model_description(variant)
        Connector._count += 1
        s = driver.instantiate(variant, unzipped(variant, unzipdir),
                               instance_name=f"{variant}-{Connector._count}", dist=DIST)
        super().__init__(variant, s, dist=DIST)
        self.start(params, init_inputs)
        self.c = s.component
        nin, nout = len(in_names), len(out_names)
        self.nin, self.nout = nin, nout
        self.vin = (fmi2ValueReference * nin)(*[self.vr[n] for n in in_names])
        self.vout = (fmi2ValueReference * nout)(*[self.vr[n] for n in out_names])
        self.xin, self.yout = (fmi2Real * nin)(), (fmi2Real * nout)()
        self.din, self.order = (fmi2Real * nin)(), (fmi2Integer * nin)(*([1] * nin))
        self.seed_c, self.dd_c = (fmi2Real * nin)(), (fmi2Real * nout)()
        # numpy views on the ctypes buffers: writing x[...] fills the FMI argument in place
        self.x, self.y, self.d = (np.ctypeslib.as_array(b) for b in (self.xin, self.yout, self.din))
        self.seed, self.dd = np.ctypeslib.as_array(self.seed_c), np.ctypeslib.as_array(self.dd_c)
        # FMU states kept by the master, per slot: 0 a step's start (rollback, iterations),
        # 1 a piece's start (the FMI 2.0 rollback to event.time inside a step of several pieces)
        self.states = [fmi2FMUstate(), fmi2FMUstate()]
        self.state_refs = [ctypes.byref(x) for x in self.states]
        # fmpy's wrappers of the C functions (argument types set, status checked)
        self._setReal, self._getReal = s.fmi2SetReal, s.fmi2GetReal
        self._setDer, self._doStep = s.fmi2SetRealInputDerivatives, s.fmi2DoStep
        self._dd, self._get, self._set = (s.fmi2GetDirectionalDerivative, s.fmi2GetFMUstate,
                                          s.fmi2SetFMUstate)
        self.ev_vr = (fmi2ValueReference * 1)(self.vr["event.time"])
        self.ev_buf = (fmi2Real * 1)()
        self._acc_buffers([self.vr[n] for n in acc_names])
        self.calls = 0          # FMI calls made through the per-step paths

    def _acc_buffers(self, refs):
        """The acceleration inputs the master writes (`acc`, `set_accelerations`), by VR."""
        self.nacc = len(refs)
        self.vacc = (ctypes.c_uint32 * self.nacc)(*refs)
        self.xacc = (ctypes.c_double * self.nacc)()
        self.acc = np.ctypeslib.as_array(self.xacc) if self.nacc else np.zeros(0)

    # --- per-step calls (prepared buffers only) ------------------------------------------------
    def set_inputs(self):
        self._setReal(self.c, self.vin, self.nin, self.xin)
        self.calls += 1

    def get_outputs(self):
        self._getReal(self.c, self.vout, self.nout, self.yout)
        self.calls += 1
        return self.y

    def set_rates(self):
        self._setDer(self.c, self.vin, self.nin, self.order, self.din)
        self.calls += 1

    def set_accelerations(self):
        """The acceleration inputs (buffer `acc`): the path with cosim.extrapolation = 3."""
        self._setReal(self.c, self.vacc, self.nacc, self.xacc)
        self.calls += 1

    def do_step(self, t, H, no_rollback=True):
        self._doStep(self.c, t, H, no_rollback)
        self.calls += 1

    def event_time(self):
        """`event.time`: the first event in the last step (t + h when none)."""
        self._getReal(self.c, self.ev_vr, 1, self.ev_buf)
        self.calls += 1
        return self.ev_buf[0]

    def directional(self, seed):
        """J·seed: derivatives of the outputs along `seed` (over the written inputs)."""
        self.seed[:] = seed
        self._dd(self.c, self.vout, self.nout, self.vin, self.nin, self.seed_c, self.dd_c)
        self.calls += 1
        return self.dd

    def save(self, slot=0):
        self._get(self.c, self.state_refs[slot])  # overwrites the slot's state in place after the first
        self.calls += 1

    def restore(self, slot=0):
        self._set(self.c, self.states[slot])
        self.calls += 1

    # --- slow paths (set-up, monitoring): driver.Connector's set and value ---------------------
    def read(self, names):
        return [self.value(n) for n in names]

    def close(self):
        if self.s is not None:
            for x in self.states:
                if x:
                    self.s.freeFMUstate(x)
            self.s.terminate()
            self.s.freeInstance()
            self.s = None


_UNZIPPED3: dict = {}


class Connector3(Connector):
    """The same connector over the FMI 3.0 FMU (DIST/fmi3/<variant>.fmu, fmpy FMU3Slave), with the
    same prepared buffers and per-step calls. FMI 3.0 has no input derivatives (`set_rates` does
    nothing: the FMU extrapolates the nodes itself, `cosim.extrapolation`). With
    `early_return` (earlyReturnAllowed) `do_step_early` stops at the first event inside the step."""

    version = 3

    def __init__(self, variant, params, init_inputs, in_names, out_names, unzipdir=None,
                 acc_names=(), early_return=True):
        path = Path(DIST) / FMI3 / f"{variant}.fmu"
        try:
            md = driver._read(str(path))
        except FileNotFoundError:
            raise SystemExit(f"error: {path} is missing; run ./scripts/run first") from None
        if unzipdir is None:
            if str(path) not in _UNZIPPED3:
                import tempfile
                from fmpy import extract
                _UNZIPPED3[str(path)] = extract(str(path), tempfile.mkdtemp(prefix=f"cosim3-{variant}-"))
            unzipdir = _UNZIPPED3[str(path)]
        self.variant, self.t = variant, 0.0
        self.vr = self.v = {v.name: v for v in md.modelVariables}
        Connector._count += 1
        s = FMU3Slave(guid=md.guid, unzipDirectory=str(unzipdir),
                      modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=f"{variant}-3-{Connector._count}")
        s.instantiate(earlyReturnAllowed=early_return)
        self.s, self.c = s, s.component
        s.enterInitializationMode(startTime=0.0)
        self.set(params)
        self.set(init_inputs)
        s.exitInitializationMode()
        nin, nout = len(in_names), len(out_names)
        self.nin, self.nout = nin, nout
        self.vin = (fmi3ValueReference * nin)(*[self.vr[n].valueReference for n in in_names])
        self.vout = (fmi3ValueReference * nout)(*[self.vr[n].valueReference for n in out_names])
        self.xin, self.yout = (fmi3Float64 * nin)(), (fmi3Float64 * nout)()
        self.din = (fmi3Float64 * nin)()
        self.seed_c, self.dd_c = (fmi3Float64 * nin)(), (fmi3Float64 * nout)()
        self.x, self.y, self.d = (np.ctypeslib.as_array(b) for b in (self.xin, self.yout, self.din))
        self.seed, self.dd = np.ctypeslib.as_array(self.seed_c), np.ctypeslib.as_array(self.dd_c)
        self.ev_vr = (fmi3ValueReference * 1)(self.vr["event.time"].valueReference)
        self.ev_buf = (fmi3Float64 * 1)()
        self._acc_buffers([self.vr[n].valueReference for n in acc_names])
        self._flags = [fmi3Boolean() for _ in range(3)]
        self._last = fmi3Float64()
        self._flag_refs = [ctypes.byref(f) for f in self._flags] + [ctypes.byref(self._last)]
        self.states = [None, None]
        self.calls = 0

    def set(self, values):
        """Parameters and inputs by name (set-up, not per step), through the FMI 3.0 setters."""
        for name, val in values.items():
            v = self.vr[name]
            {"Float64": lambda r, x: self.s.setFloat64(r, [float(x)]),
             "Int32": lambda r, x: self.s.setInt32(r, [int(x)]),
             "Boolean": lambda r, x: self.s.setBoolean(r, [bool(x)])}[v.type]([v.valueReference], val)

    def value(self, name):
        v = self.vr[name]
        return {"Float64": self.s.getFloat64, "Int32": self.s.getInt32,
                "Boolean": self.s.getBoolean}[v.type]([v.valueReference])[0]

    def set_inputs(self):
        self.s.fmi3SetFloat64(self.c, self.vin, self.nin, self.xin, self.nin)
        self.calls += 1

    def get_outputs(self):
        self.s.fmi3GetFloat64(self.c, self.vout, self.nout, self.yout, self.nout)
        self.calls += 1
        return self.y

    def set_rates(self):
        """No input derivatives in FMI 3.0."""

    def set_accelerations(self):
        self.s.fmi3SetFloat64(self.c, self.vacc, self.nacc, self.xacc, self.nacc)
        self.calls += 1

    def do_step_early(self, t, H):
        """fmi3DoStep; returns (earlyReturn, lastSuccessfulTime)."""
        self.s.fmi3DoStep(self.c, t, H, fmi3Boolean(True), *self._flag_refs)
        self.calls += 1
        return bool(self._flags[2].value), self._last.value

    def do_step(self, t, H, no_rollback=True):
        early, last = self.do_step_early(t, H)
        if early:
            raise CosimFailure(f"fmi3DoStep returned early at t = {last!r} in a method without "
                               "event location")

    def event_time(self):
        self.s.fmi3GetFloat64(self.c, self.ev_vr, 1, self.ev_buf, 1)
        self.calls += 1
        return self.ev_buf[0]

    def directional(self, seed):
        self.seed[:] = seed
        self.s.fmi3GetDirectionalDerivative(self.c, self.vout, self.nout, self.vin, self.nin,
                                            self.seed_c, self.nin, self.dd_c, self.nout)
        self.calls += 1
        return self.dd

    def save(self, slot=0):
        if self.states[slot] is None:
            self.states[slot] = self.s.getFMUState()
        else:
            self.s.fmi3GetFMUState(self.c, ctypes.byref(self.states[slot]))
        self.calls += 1

    def restore(self, slot=0):
        self.s.fmi3SetFMUState(self.c, self.states[slot])
        self.calls += 1

    def close(self):
        if self.s is not None:
            for x in self.states:
                if x is not None:
                    self.s.freeFMUState(x)
            self.s.terminate()
            self.s.freeInstance()
            self.s = None
