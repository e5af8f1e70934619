#!/usr/bin/env python3
"""Checks of the release FMUs in dist/release/ (scripts/release --check).

For every model's FMU (the five connector variants and the Body), on the binaries it actually
ships:
- every binary exports exactly the 34 FMI 2.0 functions of fmi2Functions.h and the 75 FMI 3.0
  functions of fmi3Functions.h, and nothing else;
- linux64: the highest GLIBC symbol version needed is <= 2.17;
- win64: imports only Windows system DLLs; a scene run under wine (test driver
  tests/release/fmi2_driver.c built by MinGW) gives the outputs of the same driver on the linux64
  binary: bit-equal, or within 1e-15 relative to the output's magnitude over the scene (the two C
  runtimes' libm may round differently). The Body runs two scenes, one per model;
- darwin64: a universal binary with exactly x86_64 and arm64, minimum macOS 10.12 / 11.0,
  install name @rpath/..., only system dylibs, and on arm64 a valid ad-hoc code signature (every
  page hash recomputed). It cannot be run here.
- the FMI 3.0 release FMU (dist/release/fmi3/) carries the same binaries: x86_64-linux and
  x86_64-windows byte-identical to linux64 and win64, x86_64-darwin and aarch64-darwin
  byte-identical to the slices of the universal darwin64 binary (so every check above holds for
  them too).
Usage: release_check.py <work dir> [Model ...]
The work dir must hold fmi2_driver (native), fmi2_driver.exe and bcryptprimitives.dll (test shim).
"""
import hashlib
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
from package import MODELS  # noqa: E402

# FMI 2.0 fmi2Functions.h: the 25 common functions and the 9 Co-Simulation functions.
FMI2_FUNCTIONS = frozenset("""
fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate fmi2Reset
fmi2GetReal fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal fmi2SetInteger fmi2SetBoolean
fmi2SetString fmi2GetFMUstate fmi2SetFMUstate fmi2FreeFMUstate fmi2SerializedFMUstateSize
fmi2SerializeFMUstate fmi2DeSerializeFMUstate fmi2GetDirectionalDerivative
fmi2SetRealInputDerivatives fmi2GetRealOutputDerivatives fmi2DoStep fmi2CancelStep fmi2GetStatus
fmi2GetRealStatus fmi2GetIntegerStatus fmi2GetBooleanStatus fmi2GetStringStatus
""".split())
assert len(FMI2_FUNCTIONS) == 34
# FMI 3.0 fmi3Functions.h: every function of the standard (Co-Simulation, Model Exchange and
# Scheduled Execution; the ones this FMU does not support answer fmi3Error, they still exist).
FMI3_FUNCTIONS = frozenset("""
fmi3ActivateModelPartition fmi3CompletedIntegratorStep fmi3DeserializeFMUState fmi3DoStep
fmi3EnterConfigurationMode fmi3EnterContinuousTimeMode fmi3EnterEventMode
fmi3EnterInitializationMode fmi3EnterStepMode fmi3EvaluateDiscreteStates
fmi3ExitConfigurationMode fmi3ExitInitializationMode fmi3FreeFMUState fmi3FreeInstance
fmi3GetAdjointDerivative fmi3GetBinary fmi3GetBoolean fmi3GetClock
fmi3GetContinuousStateDerivatives fmi3GetContinuousStates fmi3GetDirectionalDerivative
fmi3GetEventIndicators fmi3GetFMUState fmi3GetFloat32 fmi3GetFloat64 fmi3GetInt16 fmi3GetInt32
fmi3GetInt64 fmi3GetInt8 fmi3GetIntervalDecimal fmi3GetIntervalFraction
fmi3GetNominalsOfContinuousStates fmi3GetNumberOfContinuousStates fmi3GetNumberOfEventIndicators
fmi3GetNumberOfVariableDependencies fmi3GetOutputDerivatives fmi3GetShiftDecimal
fmi3GetShiftFraction fmi3GetString fmi3GetUInt16 fmi3GetUInt32 fmi3GetUInt64 fmi3GetUInt8
fmi3GetVariableDependencies fmi3GetVersion fmi3InstantiateCoSimulation
fmi3InstantiateModelExchange fmi3InstantiateScheduledExecution fmi3Reset fmi3SerializeFMUState
fmi3SerializedFMUStateSize fmi3SetBinary fmi3SetBoolean fmi3SetClock fmi3SetContinuousStates
fmi3SetDebugLogging fmi3SetFMUState fmi3SetFloat32 fmi3SetFloat64 fmi3SetInt16 fmi3SetInt32
fmi3SetInt64 fmi3SetInt8 fmi3SetIntervalDecimal fmi3SetIntervalFraction fmi3SetShiftDecimal
fmi3SetShiftFraction fmi3SetString fmi3SetTime fmi3SetUInt16 fmi3SetUInt32 fmi3SetUInt64
fmi3SetUInt8 fmi3Terminate fmi3UpdateDiscreteStates
""".split())
assert len(FMI3_FUNCTIONS) == 75
FMI_FUNCTIONS = FMI2_FUNCTIONS | FMI3_FUNCTIONS

MAX_GLIBC = (2, 17)
# DLLs every Windows 10 or later has (std needs Windows 10: ProcessPrng, WaitOnAddress).
WINDOWS_SYSTEM_DLLS = {"kernel32.dll", "ntdll.dll", "msvcrt.dll", "userenv.dll", "ws2_32.dll",
                       "advapi32.dll", "bcrypt.dll", "bcryptprimitives.dll",
                       "api-ms-win-core-synch-l1-2-0.dll"}
MACOS_ARCHS = {0x01000007: "x86_64", 0x0100000C: "arm64"}
MACOS_MIN = {"x86_64": (10, 12), "arm64": (11, 0)}
REL_TOL = 1e-15
STEPS, DT = 400, 1e-3

failures: list[str] = []


def fail(msg: str) -> None:
    failures.append(msg)
    print(f"  FAIL {msg}")


def ok(msg: str) -> None:
    print(f"  ok   {msg}")


def run(cmd, **kw) -> str:
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw).stdout


def check_exports(label: str, names: set[str]) -> None:
    extra, missing = sorted(names - FMI_FUNCTIONS), sorted(FMI_FUNCTIONS - names)
    if extra or missing:
        fail(f"{label}: exports {len(names)} symbols; extra {extra[:10]}{'...' if len(extra) > 10 else ''}, missing {missing}")
    else:
        ok(f"{label}: exports exactly the 34 FMI 2.0 and 75 FMI 3.0 functions")


# ------------------------------------------------------------------ linux64

def check_linux(so: Path) -> None:
    out = run(["nm", "-D", "--defined-only", so])
    check_exports("linux64", {ln.split()[-1].split("@")[0] for ln in out.splitlines() if ln.strip()})
    versions = set(re.findall(r"GLIBC_(\d+(?:\.\d+)+)", run(["objdump", "-T", so])))
    newest = max((tuple(int(p) for p in v.split(".")) for v in versions), default=(0,))
    text = ".".join(map(str, newest))
    if newest > MAX_GLIBC:
        fail(f"linux64: needs GLIBC_{text} > 2.17")
    else:
        ok(f"linux64: newest GLIBC symbol version GLIBC_{text} (<= 2.17)")
    needed = re.findall(r"NEEDED\s+(\S+)", run(["objdump", "-p", so]))
    ok(f"linux64: needs {', '.join(needed)}")


# ------------------------------------------------------------------ win64

def check_windows_static(dll: Path) -> None:
    out = run(["x86_64-w64-mingw32-objdump", "-p", dll])
    imports = re.findall(r"DLL Name: (\S+)", out)
    bad = [d for d in imports if d.lower() not in WINDOWS_SYSTEM_DLLS]
    if bad:
        fail(f"win64: imports non-system DLLs {bad}")
    else:
        ok(f"win64: imports only system DLLs: {', '.join(imports)}")
    table = out.split("[Ordinal/Name Pointer] Table", 1)
    names = set(re.findall(r"^\s*\[\s*\d+\]\s+(\S+)\s*$", table[1], re.M)) if len(table) == 2 else set()
    check_exports("win64", names)


# ------------------------------------------------------------------ darwin64

def macho_slices(data: bytes):
    magic = struct.unpack_from(">I", data)[0]
    if magic != 0xCAFEBABE:
        raise ValueError("not a universal (fat) Mach-O binary")
    (n,) = struct.unpack_from(">I", data, 4)
    for i in range(n):
        cputype, _sub, off, size, _align = struct.unpack_from(">iiIII", data, 8 + 20 * i)
        yield cputype & 0xFFFFFFFF, data[off:off + size]


def verify_adhoc_signature(sl: bytes, dataoff: int, datasize: int) -> str:
    blob = sl[dataoff:dataoff + datasize]
    magic, _length, count = struct.unpack_from(">III", blob)
    if magic != 0xFADE0CC0:
        return "no embedded signature SuperBlob"
    for i in range(count):
        _typ, off = struct.unpack_from(">II", blob, 12 + 8 * i)
        if struct.unpack_from(">I", blob, off)[0] != 0xFADE0C02:
            continue
        (_m, _l, _ver, flags, hash_off, ident_off, _nspecial, ncode, code_limit, hash_size,
         hash_type, _plat, page_log2) = struct.unpack_from(">IIIIIIIIIBBBB", blob, off)
        if not flags & 0x2:
            return f"CodeDirectory flags {flags:#x} lack CS_ADHOC"
        if hash_type != 2 or hash_size != 32:
            return f"hash type {hash_type} size {hash_size}, expected SHA-256"
        page = 1 << page_log2
        for k in range(ncode):
            want = blob[off + hash_off + 32 * k: off + hash_off + 32 * (k + 1)]
            got = hashlib.sha256(sl[k * page: min((k + 1) * page, code_limit)]).digest()
            if want != got:
                return f"page {k} hash mismatch"
        ident = blob[off + ident_off:].split(b"\0", 1)[0].decode()
        return f"ok: ad-hoc, {ncode} page hashes verified, identifier {ident}"
    return "no CodeDirectory"


def check_macos(dylib: Path) -> None:
    data = dylib.read_bytes()
    try:
        slices = list(macho_slices(data))
    except ValueError as e:
        fail(f"darwin64: {e}")
        return
    archs = sorted(MACOS_ARCHS.get(c, hex(c)) for c, _ in slices)
    if archs != ["arm64", "x86_64"]:
        fail(f"darwin64: architectures {archs}, expected arm64 and x86_64")
    else:
        ok("darwin64: universal binary, architectures arm64 + x86_64")
    for cputype, sl in slices:
        arch = MACOS_ARCHS.get(cputype, hex(cputype))
        magic, _c, _s, filetype, ncmds, _size, _flags, _res = struct.unpack_from("<IiiIIIII", sl)
        if magic != 0xFEEDFACF or filetype != 6:
            fail(f"darwin64/{arch}: not a 64-bit MH_DYLIB (magic {magic:#x}, filetype {filetype})")
            continue
        pos, minos, install, dylibs, sig = 32, None, None, [], None
        for _ in range(ncmds):
            cmd, size = struct.unpack_from("<II", sl, pos)
            if cmd == 0x32:  # LC_BUILD_VERSION
                platform, v = struct.unpack_from("<II", sl, pos + 8)
                minos = (platform, (v >> 16, (v >> 8) & 0xFF))
            elif cmd == 0x24:  # LC_VERSION_MIN_MACOSX
                (v,) = struct.unpack_from("<I", sl, pos + 8)
                minos = (1, (v >> 16, (v >> 8) & 0xFF))
            elif cmd in (0x0D, 0x0C, 0x80000018):  # LC_ID_DYLIB, LC_LOAD_DYLIB, LC_LOAD_WEAK_DYLIB
                (name_off,) = struct.unpack_from("<I", sl, pos + 8)
                name = sl[pos + name_off:pos + size].split(b"\0", 1)[0].decode()
                if cmd == 0x0D:
                    install = name
                else:
                    dylibs.append(name)
            elif cmd == 0x1D:  # LC_CODE_SIGNATURE
                sig = struct.unpack_from("<II", sl, pos + 8)
            pos += size
        want = MACOS_MIN[arch]
        if minos is None or minos[0] != 1 or minos[1] != want:
            fail(f"darwin64/{arch}: minimum OS {minos}, expected macOS {want[0]}.{want[1]}")
        else:
            ok(f"darwin64/{arch}: minimum macOS {want[0]}.{want[1]}")
        if not install or not install.startswith("@rpath/"):
            fail(f"darwin64/{arch}: install name {install!r}, expected @rpath/...")
        else:
            ok(f"darwin64/{arch}: install name {install}")
        bad = [d for d in dylibs if not d.startswith(("/usr/lib/", "/System/Library/"))]
        if bad or not dylibs:
            fail(f"darwin64/{arch}: links {dylibs}")
        else:
            ok(f"darwin64/{arch}: links only {', '.join(dylibs)}")
        trie = run(["llvm-objdump", "--macho", "--exports-trie", f"--arch={arch}", dylib])
        names = {ln.split()[-1] for ln in trie.splitlines() if re.match(r"^0x[0-9A-Fa-f]+\s+_", ln)}
        check_exports(f"darwin64/{arch}", {n[1:] for n in names if n.startswith("_")} | {n for n in names if not n.startswith("_")})
        if arch == "arm64":
            verdict = verify_adhoc_signature(sl, *sig) if sig else "no LC_CODE_SIGNATURE"
            (ok if verdict.startswith("ok") else fail)(f"darwin64/arm64: code signature {verdict}")
    print("  note darwin64 is built and inspected only: no macOS here to run it")


# ------------------------------------------------------------------ scene under wine vs linux

def bits(x: float) -> str:
    return struct.pack(">d", float(x)).hex()


def qmul(p, q):
    pw, pv, qw, qv = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[pw * qw - pv @ qv], pw * qv + qw * pv + np.cross(pv, qv)])


def axis_angle(axis, angle):
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * np.asarray(axis, float)])


def inputs_at(t: float) -> dict[str, float]:
    """Node a at rest at the origin; node b translating and spinning with a tilt (consistent
    velocities), so that springs, dampers, constraints, stops and friction all act."""
    theta, dtheta = 0.2 * math.sin(math.pi * t), 0.2 * math.pi * math.cos(math.pi * t)
    q = qmul(axis_angle([0, 0, 1], t), axis_angle([1, 0, 0], theta))
    v = {f"a.{n}[{i}]": 0.0 for n in "rvw" for i in (1, 2, 3)}
    v.update({"a.q.w": 1.0, "a.q.x": 0.0, "a.q.y": 0.0, "a.q.z": 0.0,
              "b.r[1]": 0.01 * math.sin(2 * math.pi * t), "b.r[2]": 0.002 * math.sin(3 * t),
              "b.r[3]": 0.1 + 0.001 * math.cos(5 * t),
              "b.v[1]": 0.02 * math.pi * math.cos(2 * math.pi * t), "b.v[2]": 0.006 * math.cos(3 * t),
              "b.v[3]": -0.005 * math.sin(5 * t),
              "b.q.w": q[0], "b.q.x": q[1], "b.q.y": q[2], "b.q.z": q[3],
              "b.w[1]": dtheta * math.cos(t), "b.w[2]": dtheta * math.sin(t), "b.w[3]": 1.0})
    return v


def parameters(names: set[str]) -> dict[str, float]:
    p = {}
    for n in names:
        m = re.fullmatch(r"elasticity\.k(\d)", n)
        if m:
            p[n] = 1e4 if int(m.group(1)) <= 3 else 100.0
        m = re.fullmatch(r"damping\.c(\d)", n)
        if m:
            p[n] = 1.0 if int(m.group(1)) <= 3 else 0.1
        m = re.fullmatch(r"stop\.upper(\d)", n)
        if m:
            p[n] = 0.005 if int(m.group(1)) <= 3 else 0.1
    p.update({k: val for k, val in {"friction.muStatic": 0.3, "friction.muKinetic": 0.2,
                                    "friction.R": 0.01}.items() if k in names})
    return p


def real_variables(md: ET.Element, ty: str = "Real") -> dict[str, tuple[int, str]]:
    """name -> (value reference, causality) of every variable of type `ty`."""
    return {sv.get("name"): (int(sv.get("valueReference")), sv.get("causality"))
            for sv in md.iter("ScalarVariable") if sv.find(ty) is not None}


def output_names(md: ET.Element) -> list[str]:
    """The Real outputs in the order the scene reads them (by value reference)."""
    real = real_variables(md)
    return [n for n, (vr, c) in sorted(real.items(), key=lambda kv: kv[1][0]) if c == "output"]


def scene_script(md: ET.Element) -> str:
    real = real_variables(md)
    params = parameters({n for n, (_, c) in real.items() if c == "parameter"})
    outputs = [real[n][0] for n in output_names(md)]
    get = f"G {len(outputs)} " + " ".join(map(str, outputs))
    lines = [f"I {md.get('guid')}"]
    lines += [f"S {real[n][0]} {bits(val)}" for n, val in sorted(params.items())]

    def set_inputs(t):
        return [f"S {real[n][0]} {bits(val)}" for n, val in inputs_at(t).items() if n in real]

    lines += set_inputs(0.0) + ["E", "X", get]
    for k in range(STEPS):
        t = k * DT
        lines += set_inputs(t) + [f"D {bits(t)} {bits(DT)}", get]
    lines.append("T")
    return "\n".join(lines) + "\n"


def body_scene_script(md: ET.Element, model: int) -> str:
    """The Body under gravity and a force and moment varying with time, 400 steps of 1 ms.
    Model 0: a spring along x, a prescribed y, a free z and a free rotation about z (cos, sin,
    atan2, sqrt of the exact updates); model 1: a tumbling rigid body (RK4 in substeps)."""
    real, ints = real_variables(md), real_variables(md, "Integer")
    q0 = axis_angle([0, 0, 1], 0.3) if model == 0 else qmul(axis_angle([0, 0, 1], 0.3), axis_angle([1, 0, 0], 0.7))
    params = {"mass": 2.0, "inertia[1]": 0.4, "inertia[2]": 1.1, "inertia[3]": 2.3, "gravity[1]": 0.3,
              "gravity[3]": -9.81, "start.r[1]": 0.05, "start.v[2]": 0.7, "start.w[3]": 2.0,
              **dict(zip(["start.q.w", "start.q.x", "start.q.y", "start.q.z"], q0))}
    if model == 0:
        params["spring.k[1]"] = 40.0
        integers = {"model": 0, "dof.r[2]": 2, "dof.w[3]": 1}
    else:
        params.update({"start.w[1]": 3.0, "start.w[2]": -2.0, "rigid.maxTurn": 0.05})
        integers = {"model": 1}
    outputs = [real[n][0] for n in output_names(md)]
    get = f"G {len(outputs)} " + " ".join(map(str, outputs))
    lines = [f"I {md.get('guid')}", "E"]
    lines += [f"N {ints[n][0]} {x}" for n, x in integers.items()]
    lines += [f"S {real[n][0]} {bits(x)}" for n, x in params.items()]
    lines += ["X", get]
    for k in range(STEPS):
        t = k * DT
        load = {"f[1]": math.sin(3 * t), "f[2]": 0.5 * math.cos(2 * t), "f[3]": 1.0,
                "m[1]": 0.2 * math.sin(5 * t), "m[2]": -0.1, "m[3]": 0.3 * math.cos(t)}
        lines += [f"S {real[n][0]} {bits(x)}" for n, x in load.items()]
        lines += [f"D {bits(t)} {bits(DT)}", get]
    lines.append("T")
    return "\n".join(lines) + "\n"


def scenes(model: str, md: ET.Element) -> list[tuple[str, str]]:
    """(label, driver script) of each scene a model's FMU runs under wine."""
    if model == "Body":
        return [("Body-axes", body_scene_script(md, 0)), ("Body-rigid", body_scene_script(md, 1))]
    return [(model, scene_script(md))]


def read_bits(path: Path) -> np.ndarray:
    rows = [[struct.unpack(">d", bytes.fromhex(w))[0] for w in ln.split()] for ln in path.read_text().splitlines()]
    return np.array(rows)


def compare_under_wine(variant: str, script: str, md: ET.Element, so: Path, dll: Path, work: Path) -> None:
    """Runs the driver `script` (scene `variant`) on the linux64 and, under wine, the win64
    binary and compares every output."""
    d = work / variant
    d.mkdir(exist_ok=True)
    (d / "scene.txt").write_text(script)
    shutil.copy(dll, d / f"{variant}.dll")
    shutil.copy(work / "bcryptprimitives.dll", d / "bcryptprimitives.dll")  # test-only shim
    run([str(work / "fmi2_driver"), str(so), str(d / "scene.txt"), str(d / "linux.txt")])
    env = {**os.environ, "WINEPREFIX": str(work / "wineprefix"), "WINEDEBUG": "-all",
           "WINEDLLOVERRIDES": "mscoree,mshtml="}
    cmd = [wine(), str(work / "fmi2_driver.exe"), f"{variant}.dll", "scene.txt", "windows.txt"]
    r = subprocess.run(cmd, cwd=d, env=env, capture_output=True, text=True)
    if r.returncode != 0 and "wine client error" in r.stderr:
        # wine's own client lost its wineserver, not the driver failing (scripts/release keeps one
        # server alive for the whole check to prevent this): said, and run once more
        print(f"  note win64 under wine: {variant}: {r.stderr.strip()[-200:]}; running the driver again")
        r = subprocess.run(cmd, cwd=d, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"win64 under wine: {variant} driver exit code {r.returncode}: {r.stderr.strip()[-500:]}")
        return
    a, b = read_bits(d / "linux.txt"), read_bits(d / "windows.txt")
    if a.shape != b.shape:
        fail(f"win64 under wine: {variant} output shapes {a.shape} vs {b.shape}")
        return
    equal = (a == b) | (np.isnan(a) & np.isnan(b))
    # Differences come from single libm calls (msvcrt/MinGW vs glibc, each within an ulp or two) and
    # the arithmetic after them, so they scale with the magnitudes that enter an output: the
    # tolerance is relative to max(|a|, |b|, largest |value| of that output over the scene).
    scale = np.nanmax(np.abs(np.where(np.isfinite(a), a, np.nan)), axis=0, initial=0.0)
    # A node moment is a sum of lever × force terms (d × F and the like), which can cancel to far
    # less than the terms themselves; an ulp of those terms is then many ulps of the moment (the
    # moment about a.3 of ProjectionCartesian: 28 N·m at one row, made of terms ≈ 5e3 N·m). Its
    # scale is at least the scene's largest |x_b − x_a| times its largest node force.
    names = output_names(md)
    cols = lambda pattern: [j for j, n in enumerate(names) if re.fullmatch(pattern, n)]  # noqa: E731
    forces, moments = cols(r"[ab]\.f\[\d\]"), cols(r"[ab]\.m\[\d\]")
    if forces and moments:
        lever = max(math.dist([inputs_at(k * DT)[f"a.r[{i}]"] for i in (1, 2, 3)],
                              [inputs_at(k * DT)[f"b.r[{i}]"] for i in (1, 2, 3)])
                    for k in range(STEPS + 1))
        scale[moments] = np.maximum(scale[moments], lever * scale[forces].max())
    with np.errstate(invalid="ignore", divide="ignore"):
        diff = np.where(equal, 0.0, np.abs(a - b))
        rel = np.where(equal, 0.0, diff / np.maximum(np.abs(a), np.abs(b)))
        rel_scaled = np.where(equal, 0.0, diff / np.maximum(np.maximum(np.abs(a), np.abs(b)), scale))
    worst, worst_scaled = float(np.max(rel)), float(np.max(rel_scaled))
    i, j = np.unravel_index(int(np.argmax(rel)), rel.shape)
    msg = (f"win64 under wine: {variant}: {a.size} outputs ({a.shape[0]} rows), {int(equal.sum())} bit-equal "
           f"({100 * equal.mean():.2f} %), worst relative difference {worst:.3g}")
    if worst > 0:
        msg += (f" (row {i}, column {j}: {a[i, j]!r} vs {b[i, j]!r}, absolute {diff[i, j]:.3g}), "
                f"worst relative to the output's scale {worst_scaled:.3g}")
    (ok if worst_scaled <= REL_TOL and np.isfinite(worst_scaled) else fail)(msg)


def wine() -> str:
    for w in ("wine64", "/usr/lib/wine/wine64", "wine"):
        if shutil.which(w):
            return shutil.which(w)
    sys.exit("error: wine64 not found (scripts/release installs it with apt-get)")


# ------------------------------------------------------------------ main

def check_fmi3_twin(variant: str, bins: dict[str, Path]) -> None:
    """The FMI 3.0 release FMU holds the FMI 2.0 release FMU's binaries (per architecture)."""
    fmu = REPO / "dist" / "release" / "fmi3" / f"{variant}.fmu"
    print(f"== {fmu.relative_to(REPO)}")
    slices = {MACOS_ARCHS.get(c): sl for c, sl in macho_slices(bins["darwin64"].read_bytes())}
    want = {
        f"binaries/x86_64-linux/{variant}.so": bins["linux64"].read_bytes(),
        f"binaries/x86_64-windows/{variant}.dll": bins["win64"].read_bytes(),
        f"binaries/x86_64-darwin/{variant}.dylib": slices.get("x86_64"),
        f"binaries/aarch64-darwin/{variant}.dylib": slices.get("arm64"),
    }
    with zipfile.ZipFile(fmu) as zf:
        md = ET.fromstring(zf.read("modelDescription.xml"))
        if md.get("fmiVersion") != "3.0":
            fail(f"fmi3/{variant}: fmiVersion {md.get('fmiVersion')!r}")
        present = set(zf.namelist())
        for name, data in want.items():
            if name not in present:
                fail(f"fmi3/{variant}: {name} missing")
            elif data is None or zf.read(name) != data:
                fail(f"fmi3/{variant}: {name} differs from the FMI 2.0 release binary")
            else:
                ok(f"fmi3/{variant}: {name} is the checked FMI 2.0 release binary")


def main() -> None:
    work = Path(sys.argv[1]).resolve()
    variants = sys.argv[2:] or MODELS
    for v in variants:
        fmu = REPO / "dist" / "release" / f"{v}.fmu"
        print(f"== {fmu.relative_to(REPO)}")
        d = work / v
        d.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(fmu) as zf:
            md = ET.fromstring(zf.read("modelDescription.xml"))
            bins = {}
            for plat, ext in (("linux64", "so"), ("win64", "dll"), ("darwin64", "dylib")):
                p = d / f"{plat}.{ext}"
                p.write_bytes(zf.read(f"binaries/{plat}/{v}.{ext}"))
                p.chmod(0o755)
                bins[plat] = p
        check_linux(bins["linux64"])
        check_windows_static(bins["win64"])
        check_macos(bins["darwin64"])
        for label, script in scenes(v, md):
            compare_under_wine(label, script, md, bins["linux64"], bins["win64"], work)
        check_fmi3_twin(v, bins)
    if failures:
        print(f"release check: {len(failures)} failure(s)")
        sys.exit(1)
    print("release check: all passed")


if __name__ == "__main__":
    main()
