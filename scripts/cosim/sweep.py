"""Sweeps of the scenes of scenes.py over FMU parameters and scene settings, serially in this
process or on Dask distributed (a local cluster, one single-threaded worker process per core, or
an existing cluster given by its scheduler address). The command is ./scripts/sweep; the charts
(scripts/charts) run through the same engine. Documentation: docs/sweeps.md.

A task is a plain dict (`spec`): its kind ("run": one simulation and its figures; "reference":
a scene's reference (the belt's monolithic one) that the runs' error is measured against; "stability": one
(method, ζ) point of the §7 stability map), the scene, the scene settings and FMU values that
differ from the scene's own, and for runs the coupling method and the macro step H. Its row key
is a hash of the spec and of the FMU file's sha256, so a row is recomputed only when an input or
the FMU changes.

What travels to the workers (no checkout, no shared file system):
  - the Python package scripts/cosim (as a zip) and the FMU files the sweep uses, in one worker
    plugin, sent once per worker; on each worker the plugin writes the zip into the worker's
    local directory (put on sys.path) and each FMU into <local dir>/connector-fmus/<sha256>/,
    extracted there once;
  - per task, only the spec (a few hundred bytes).
A worker needs Python 3 (the client's minor version) with the pinned requirements.txt installed
(numpy, fmpy, dask, distributed and their dependencies), on Linux x86-64 (the FMUs' binaries).
"""
from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import json
import math
import os
import socket
import sys
import threading
import time
import zipfile
from pathlib import Path

import numpy as np

from . import connectors as _connectors
from . import master as _master
from .master import ALL_METHODS, METHODS, simulate, split_method
from .scenes import SCENES, OneStepMap, largest_stable, spectral_radius

PACKAGE_DIR = Path(__file__).resolve().parent

# Scene attributes that are descriptions, not settings (cannot be swept).
NOT_SETTINGS = {"name", "title", "variant", "sweep", "record", "error_label", "error2_label",
                "fine", "fine_values"}
RUN_SETTINGS = ("method", "H")
FIXED_COLUMNS = ["key", "kind", "scene", "method", "H"]
RESULT_COLUMNS = ["status", "message", "cpu_s", "task_cpu_s", "steps", "fmi_calls",
                  "rollback_passes", "worker", "host_pid"]


# =================================================================================================
# scenes with settings and FMU values
# =================================================================================================
def scene_settings(scene) -> dict:
    """The settings of a scene that a sweep may change: plain (number, string, tuple) attributes
    of the scene (class or instance), with their current values."""
    out = {}
    for cls in reversed(type(scene).__mro__):
        for k, v in vars(cls).items():
            if k.startswith("_") or k in NOT_SETTINGS or isinstance(v, (property, classmethod,
                                                                         staticmethod)):
                continue
            if isinstance(v, (bool, int, float, str, tuple)) and not callable(v):
                out[k] = v
    for k, v in vars(scene).items():
        if not k.startswith("_") and k not in NOT_SETTINGS:
            out[k] = v
    return out


def make_scene(name, settings=None, fmu=None):
    """A fresh scene `name` of scenes.SCENES with `settings` (scene attributes) changed and the
    FMU values `fmu` set in initialisation after the scene's own parameters."""
    if name not in SCENES:
        raise ValueError(f"unknown scene {name!r}; known: {', '.join(SCENES)}")
    base = SCENES[name]
    cls = type(base)
    known = scene_settings(base)
    kw = dict(vars(base))
    for k, v in (settings or {}).items():
        if k not in known:
            raise ValueError(f"scene {name}: unknown setting {k!r}")
        kw[k] = tuple(v) if isinstance(known[k], tuple) else v
    if fmu:
        own = cls.params
        values = dict(fmu)
        cls = type(cls.__name__, (cls,), {
            "params": property(lambda self: {**(own.fget(self) if isinstance(own, property)
                                                 else own), **values})})
    return cls(**kw)


def coerce_setting(scene_name, key, value):
    """A grid value for scene setting `key` in the type of the scene's own value."""
    if key == "method":
        if split_method(value)[0] not in ALL_METHODS:
            raise ValueError(f"unknown method {value!r}; known: {', '.join(ALL_METHODS)} "
                             "(event-located ones also as METHOD@fmi3)")
        return value
    if key == "H":
        return float(value)
    cur = scene_settings(SCENES[scene_name])[key]
    if isinstance(cur, bool):
        return value if isinstance(value, bool) else str(value).lower() in ("1", "true", "yes")
    if isinstance(cur, int):
        f = float(value)
        if f != int(f):
            raise ValueError(f"{key} takes an integer, not {value!r}")
        return int(f)
    if isinstance(cur, float):
        return float(value)
    if isinstance(cur, tuple):
        parts = value if isinstance(value, (list, tuple)) else str(value).split(":")
        return tuple(float(p) for p in parts)
    return str(value)


# =================================================================================================
# FMU files: client side (read, hash) and worker side (install once, find)
# =================================================================================================
def fmu_file(variant) -> Path:
    path = Path(_connectors.DIST) / f"{variant}.fmu"
    if not path.is_file():
        raise SystemExit(f"error: {path} is missing; run ./scripts/run first")
    return path


def fmu_ref(variant) -> dict:
    data = fmu_file(variant).read_bytes()
    return {"variant": variant, "sha256": hashlib.sha256(data).hexdigest(),
            "path": str(fmu_file(variant))}


def code_zip() -> bytes:
    """The package scripts/cosim as a zip (its .py files), for the workers."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for p in sorted(PACKAGE_DIR.glob("*.py")):
            info = zipfile.ZipInfo(f"cosim/{p.name}", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            zf.writestr(info, p.read_bytes())
    return buf.getvalue()


def _plugin_class():
    """The worker plugin carrying the code zip and the FMU files. Defined inside a function so
    that cloudpickle sends the class itself (by value): a worker unpickles it before it has the
    package. Its methods use the standard library only."""
    from distributed.diagnostics.plugin import WorkerPlugin

    class ConnectorSweepFiles(WorkerPlugin):
        def __init__(self, code, code_sha, fmus):
            self.code, self.code_sha, self.fmus = code, code_sha, fmus   # fmus: sha -> (variant, bytes)

        def setup(self, worker):
            import importlib
            import os as _os
            import sys as _sys
            import zipfile as _zipfile
            root = _os.path.join(worker.local_directory, "connector-fmus")
            for sha, (variant, data) in self.fmus.items():
                d = _os.path.join(root, sha)
                done = _os.path.join(d, ".installed")
                if _os.path.exists(done):
                    continue                               # extracted once per worker
                _os.makedirs(_os.path.dirname(_os.path.join(d, f"{variant}.fmu")), exist_ok=True)
                with open(_os.path.join(d, f"{variant}.fmu"), "wb") as f:
                    f.write(data)
                with _zipfile.ZipFile(_os.path.join(d, f"{variant}.fmu")) as zf:
                    zf.extractall(_os.path.join(d, "unzipped"))
                open(done, "w").close()
            zpath = _os.path.join(worker.local_directory, f"cosim-{self.code_sha[:16]}.zip")
            if not _os.path.exists(zpath):
                with open(zpath, "wb") as f:
                    f.write(self.code)
            if zpath not in _sys.path:
                _sys.path.insert(0, zpath)
            if getattr(worker, "connector_code_sha", self.code_sha) != self.code_sha:
                for name in [m for m in _sys.modules if m == "cosim" or m.startswith("cosim.")]:
                    del _sys.modules[name]                 # another version: import this one
            importlib.invalidate_caches()
            importlib.import_module("cosim.sweep")
            worker.connector_code_sha = self.code_sha

    return ConnectorSweepFiles


_LOCAL_EXTRACTED: dict = {}
_DIST_LOCK = threading.Lock()


def _installed(ref):
    """(directory holding <variant>.fmu, unzip directory) of an FMU on this process: on a Dask
    worker the plugin's copy (waits for the plugin if the task came first), else dist/ extracted
    once into a temporary directory."""
    try:
        from distributed import get_worker
        worker = get_worker()
    except (ImportError, ValueError):
        worker = None
    if worker is None:
        sha = ref["sha256"]
        if sha not in _LOCAL_EXTRACTED:
            import tempfile
            from fmpy import extract
            path = Path(ref["path"])
            if hashlib.sha256(path.read_bytes()).hexdigest() != sha:
                raise RuntimeError(f"{path} changed during the sweep")
            # the dist directory: variant "fmi3/Planar" lives in <dist>/fmi3/Planar.fmu
            _LOCAL_EXTRACTED[sha] = (str(path.parents[len(Path(ref["variant"]).parts) - 1]), extract(
                str(path), tempfile.mkdtemp(prefix=f"sweep-{Path(ref['variant']).name}-")))
        return _LOCAL_EXTRACTED[sha]
    d = Path(worker.local_directory) / "connector-fmus" / ref["sha256"]
    for _ in range(600):
        if (d / ".installed").exists():
            return str(d), str(d / "unzipped")
        time.sleep(0.1)
    raise RuntimeError(f"FMU {ref['variant']} ({ref['sha256'][:12]}) was not installed on this worker")


@contextlib.contextmanager
def _fmu_from(ref):
    """Point the connectors' FMU lookup (connectors.DIST, read by model_description) at this FMU's
    directory for one task."""
    d, unzipdir = _installed(ref)
    with _DIST_LOCK:
        if str(_connectors.DIST) != d:
            _connectors.DIST = Path(d)
        yield unzipdir


def _remote_run_task():
    """run_task behind a function that cloudpickle sends by value (it is local to this one): the
    scheduler unpickles the task graph, and it has no copy of this package; the worker imports
    the package (from the plugin's zip) only when it runs the task."""
    def run(spec, ref, reference=None):
        import importlib
        return importlib.import_module("cosim.sweep").run_task(spec, ref, reference)
    return run


def _where():
    try:
        from distributed import get_worker
        return get_worker().address
    except (ImportError, ValueError):
        return "serial"


# =================================================================================================
# tasks (run on a worker or in this process)
# =================================================================================================
def _figures_of(res, scene):
    fig = scene.measure(res)
    return {k: (float(v) if isinstance(v, (float, np.floating)) else
                int(v) if isinstance(v, (int, np.integer)) else v) for k, v in fig.items()}


def _task_run(spec, unzipdir, reference):
    scene = make_scene(spec["scene"], spec.get("settings"), spec.get("fmu"))
    if reference is not None:
        scene.fine_values = reference
    res = simulate(scene, spec["method"], spec["H"], unzipdir=unzipdir, record=scene.record)
    row = {"cpu_s": res.cpu, "steps": res.steps, "fmi_calls": res.calls,
           "rollback_passes": res.iterations}
    if res.failed:
        row["status"], row["message"] = "failed", res.failed
    row["figures"] = _figures_of(res, scene)
    row["figures"]["events"] = int(getattr(res, "events", 0))
    return row


def _task_reference(spec, unzipdir, _):
    """The scene's reference figures (`Scene.fine_reference`: the belt's monolithic reference),
    which its runs' `error` is measured against."""
    scene = make_scene(spec["scene"], spec.get("settings"), spec.get("fmu"))
    c0 = time.process_time()
    figures = scene.fine_reference(unzipdir)
    return {"cpu_s": time.process_time() - c0, "steps": 0, "fmi_calls": 0, "rollback_passes": 0,
            "figures": {k: v for k, v in figures.items() if not isinstance(v, (list, tuple))}}


def _task_stability(spec, unzipdir, _):
    """Largest stable ωH of one method at one ζ (scripts/stability_map.py), and at ζ = 0 the
    spectral radius on spec['rho_at'] (the same probe: its evaluation count includes them)."""
    probe = OneStepMap(spec["method"], spec["zeta"], unzipdir=unzipdir)
    c0 = time.process_time()
    try:
        tol = spec["tol"]
        hmax = largest_stable(lambda h: probe.rho(h) <= 1 + tol, spec["h_lo"], spec["h_hi"])
        rho = [probe.rho(h) for h in spec.get("rho_at", [])]
    finally:
        probe.close()
    return {"cpu_s": time.process_time() - c0,
            "figures": {"largest_stable_omegaH": hmax, "evaluations": probe.evaluations,
                        **({"rho": rho} if rho else {})}}


KINDS = {"run": _task_run, "reference": _task_reference, "stability": _task_stability}


def run_task(spec, ref, reference=None):
    """Do one task; never raises: an exception becomes a row with status "error" and its message
    (with the FMU's log lines, which name e.g. the refused parameter)."""
    if isinstance(reference, dict) and "figures" in reference:          # a reference row
        reference = reference["figures"] if reference.get("status") == "ok" else None
    c0 = time.process_time()
    row = {"key": spec["key"], "status": "ok", "message": "", "worker": _where(),
           "host_pid": f"{socket.gethostname()}:{os.getpid()}"}
    log = io.StringIO()
    try:
        with _fmu_from(ref) as unzipdir, contextlib.redirect_stdout(log):
            row.update(KINDS[spec["kind"]](spec, unzipdir, reference))
    except Exception as e:   # noqa: BLE001 - any failure of a run is its row's message
        row["status"] = "error"
        row["message"] = f"{type(e).__name__}: {e}"
    fmu_log = " | ".join(line.strip() for line in log.getvalue().splitlines() if line.strip())
    if row["status"] != "ok" and fmu_log:
        row["message"] += f" [FMU log: {fmu_log[:2000]}]"
    row["task_cpu_s"] = time.process_time() - c0
    return row


# =================================================================================================
# the sweep: tasks, keys, the rows file
# =================================================================================================
def _jsonable(v):
    if isinstance(v, tuple):
        return list(v)
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    return v


def make_task(kind, scene=None, method=None, H=None, settings=None, fmu=None, variant=None,
              fmu_sha=None, needs=None, cost=1.0, **extra):
    """A task spec with its key: sha256 of the inputs (and of the FMU file) in canonical JSON."""
    spec = {"kind": kind, "scene": scene, "method": method, "H": H,
            "settings": {k: _jsonable(v) for k, v in sorted((settings or {}).items())},
            "fmu": {k: _jsonable(v) for k, v in sorted((fmu or {}).items())},
            **{k: _jsonable(v) for k, v in extra.items()}}
    spec["key"] = hashlib.sha256(json.dumps({**spec, "fmu_sha256": fmu_sha}, sort_keys=True)
                                 .encode()).hexdigest()[:20]
    return {"spec": spec, "variant": variant, "needs": needs, "cost": cost}


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (list, tuple, dict)):
        return json.dumps(v)
    return str(v)


def _parse(v):
    if v == "":
        return None
    try:
        return int(v)
    except ValueError:
        pass
    try:
        return float(v)
    except ValueError:
        pass
    if v[:1] in "[{":
        with contextlib.suppress(ValueError):
            return json.loads(v)
    return v


class RowsFile:
    """The sweep's CSV: one row per task, appended (and flushed) as each finishes. Columns: the
    key, the inputs, the result columns, then the figures (from the first row with figures; any
    figure not in the header goes to the last column, "other", as JSON). A truncated last line
    (a crash while writing) is dropped on reopening."""

    def __init__(self, path, input_columns):
        self.path = Path(path)
        self.inputs = list(input_columns)
        self.header = None
        self.done = {}
        self._pending = []
        if self.path.is_file() and self.path.stat().st_size:
            raw = self.path.read_bytes()
            if not raw.endswith(b"\n"):
                raw = raw[:raw.rfind(b"\n") + 1]
                self.path.write_bytes(raw)
            rows = list(csv.reader(io.StringIO(raw.decode())))
            if rows:
                self.header = rows[0]
                missing = [c for c in self.inputs if c not in self.header]
                if missing:
                    raise SystemExit(f"error: {self.path} has no column for {', '.join(missing)} "
                                     "(written by a sweep over other axes); use another --out")
                for r in rows[1:]:
                    d = dict(zip(self.header, r))
                    self.done[d["key"]] = self._row_of(d)

    def _row_of(self, d):
        fixed = set(FIXED_COLUMNS + self.inputs + RESULT_COLUMNS + ["other"])
        row = {k: _parse(v) for k, v in d.items() if k in RESULT_COLUMNS or k == "key"}
        row["message"] = d.get("message", "")
        row["status"] = d.get("status", "")
        figs = {k: _parse(v) for k, v in d.items() if k not in fixed and v != ""}
        if d.get("other"):
            figs.update(json.loads(d["other"]))
        row["figures"] = figs
        return row

    def append(self, spec, inputs, row):
        self._pending.append((spec, inputs, row))
        if self.header is None and not row.get("figures") and len(self._pending) < 64:
            return                  # wait for a row with figures to fix the header
        if self.header is None:
            figs = next((r.get("figures") for _, _, r in self._pending if r.get("figures")), {})
            self.header = (FIXED_COLUMNS + [c for c in self.inputs if c not in FIXED_COLUMNS]
                           + RESULT_COLUMNS + list(figs) + ["other"])
            with open(self.path, "w", newline="") as f:
                csv.writer(f).writerow(self.header)
        self.flush()

    def flush(self):
        if not self._pending:
            return
        if self.header is None:
            self.header = FIXED_COLUMNS + self.inputs + RESULT_COLUMNS + ["other"]
            with open(self.path, "w", newline="") as f:
                csv.writer(f).writerow(self.header)
        buf = io.StringIO()
        w = csv.writer(buf)
        for spec, inputs, row in self._pending:
            figs = dict(row.get("figures") or {})
            cells = {"key": spec["key"], "kind": spec["kind"], "scene": spec["scene"],
                     "method": spec.get("method"), "H": spec.get("H"), **inputs,
                     **{k: row.get(k) for k in RESULT_COLUMNS}}
            for k in list(figs):
                if k in self.header and k not in cells:
                    cells[k] = figs.pop(k)
            cells["other"] = figs or None
            w.writerow([_cell(cells.get(k)) for k in self.header])
            self.done[spec["key"]] = row
        with open(self.path, "a", newline="") as f:   # whole lines, one write, flushed
            f.write(buf.getvalue())
        self._pending.clear()


class Progress:
    """A console progress bar on stderr: tasks done / total, failures so far, elapsed time."""

    def __init__(self, total, done=0, stream=None, enabled=True):
        self.total, self.done, self.failed = total, done, 0
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.tty = self.stream.isatty()
        self.t0 = time.monotonic()
        self._last = -1.0
        self.draw(force=True)

    def line(self):
        width = 30
        frac = self.done / self.total if self.total else 1.0
        bar = "#" * int(round(width * frac)) + "-" * (width - int(round(width * frac)))
        el = time.monotonic() - self.t0
        return (f"[{bar}] {self.done}/{self.total} done, {self.failed} failed, "
                f"{int(el // 60)}:{int(el % 60):02d} elapsed")

    def draw(self, force=False):
        if not self.enabled:
            return
        if self.tty:
            self.stream.write("\r" + self.line())
            self.stream.flush()
        else:   # a log file: a line every 10 % (and at the end)
            step = math.floor(10 * self.done / max(self.total, 1))
            if force or step > self._last:
                self._last = step
                self.stream.write(self.line() + "\n")
                self.stream.flush()

    def note(self, text):
        """Print a line above the bar."""
        if self.enabled and self.tty:
            self.stream.write("\r\033[K")
        print(text, flush=True)
        self.draw(force=False)

    def update(self, status):
        self.done += 1
        self.failed += status != "ok"
        self.draw()

    def close(self):
        if self.enabled and self.tty:
            self.stream.write("\n")
            self.stream.flush()


def local_cluster(workers=None):
    """A local Dask cluster: one single-threaded worker process per core (or `workers`)."""
    import logging
    from distributed import LocalCluster
    n = workers or os.cpu_count() or 1
    return LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                        dashboard_address=None, silence_logs=logging.ERROR)


def execute(tasks, scheduler=None, out=None, input_columns=(), inputs_of=None, progress=True,
            log=None, workers=None):
    """Run `tasks` (make_task dicts) and return their rows in the tasks' order.

    scheduler: None = serially in this process; "local" = a local cluster (`workers` processes,
    default one per core); "tcp://HOST:PORT" = that cluster. out: a CSV to append rows to and
    resume from (tasks whose key is already there are not run again). `log(task, row)` is called
    as each row arrives (progress lines)."""
    inputs_of = inputs_of or (lambda spec: {})
    rows_file = RowsFile(out, input_columns) if out else None
    done = dict(rows_file.done) if rows_file else {}
    todo = [t for t in tasks if t["spec"]["key"] not in done]
    skipped = len(tasks) - len(todo)
    if rows_file is not None and skipped:
        print(f"==> {skipped} of {len(tasks)} rows already in {out}; computing {len(todo)}",
              flush=True)
    refs = {v: fmu_ref(v) for v in sorted({t["variant"] for t in todo})}
    bar = Progress(len(tasks), skipped, enabled=progress)
    results = {}

    def finished(task, row):
        results[task["spec"]["key"]] = row
        if rows_file is not None:
            rows_file.append(task["spec"], inputs_of(task["spec"]), row)
        bar.update(row["status"])
        if log:
            bar.note(log(task, row))

    try:
        if scheduler is None:
            for t in sorted(todo, key=lambda t: t["needs"] is not None):   # references first
                ref = None
                if t["needs"]:
                    ref = results.get(t["needs"]) or done.get(t["needs"])
                finished(t, run_task(t["spec"], refs[t["variant"]], ref))
        else:
            _execute_dask(todo, scheduler, refs, done, finished, workers)
    finally:
        if rows_file is not None:
            rows_file.flush()
        bar.close()
    return [results.get(t["spec"]["key"]) or done[t["spec"]["key"]] for t in tasks]


def _execute_dask(todo, scheduler, refs, done, finished, workers):
    from distributed import Client, as_completed
    cluster = local_cluster(workers) if scheduler == "local" else None
    client = Client(cluster if cluster is not None else scheduler)
    try:
        fmus = {}
        for v, r in refs.items():
            fmus[r["sha256"]] = (v, Path(r["path"]).read_bytes())
        code = code_zip()
        code_sha = hashlib.sha256(code).hexdigest()
        plugin = _plugin_class()(code, code_sha, fmus)
        digest = hashlib.sha256((code_sha + "".join(sorted(fmus))).encode()).hexdigest()[:16]
        client.register_plugin(plugin, name=f"connector-sweep-{digest}")
        shipped = {r["variant"]: {k: r[k] for k in ("variant", "sha256")} for r in refs.values()}
        futures, by_key = {}, {t["spec"]["key"]: t for t in todo}
        entry = _remote_run_task()
        token = os.urandom(4).hex()
        # longest first (estimated cost; a reference before everything): the runs that wait for
        # a reference (belt, the longest) start as soon as it is done, short tasks fill the end
        order = sorted(todo, key=lambda t: -t["cost"])
        n = len(order)
        for i, t in enumerate(order):
            ref_arg = None
            if t["needs"]:
                ref_arg = futures.get(t["needs"]) or done.get(t["needs"])
            key = f"{t['spec']['kind']}-{t['spec']['key']}-{token}"    # unique to this sweep
            futures[t["spec"]["key"]] = client.submit(
                entry, t["spec"], shipped[t["variant"]], ref_arg, key=key, pure=False,
                priority=(n - i) + (10 * n if t["spec"]["kind"] == "reference" else 0))
        key_of = {f.key: k for k, f in futures.items()}
        for fut in as_completed(list(futures.values())):
            k = key_of[fut.key]
            try:
                row = fut.result()
            except Exception as e:   # noqa: BLE001 - e.g. KilledWorker: the task killed workers
                row = {"key": k, "status": "error", "message": f"{type(e).__name__}: {e}",
                       "worker": "", "host_pid": ""}
            finished(by_key[k], row)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


# =================================================================================================
# the command: ./scripts/sweep SCENE NAME=VALUES ... [--scheduler ...] [--out FILE.csv]
# =================================================================================================
METHOD_COST = {"zoh": 1.0, "extrapolation": 1.5, "linear_implicit": 3.0, "rollback": 4.0,
               "extrapolation_ev": 1.5, "linear_implicit_ev": 3.5, "linear_exact_ev": 6.0,
               "linear_path_ev": 4.0}


def run_cost(scene, method, H):
    """A rough relative cost (FMU steps weighted by the method's calls per step), to start the
    longest tasks first."""
    return scene.t_end / H * METHOD_COST.get(split_method(method)[0], 1.0)


def split_values(text):
    """'a,b,lin(0,1,5)' -> ['a', 'b', 'lin(0,1,5)'] (commas inside parentheses kept)."""
    out, depth, cur = [], 0, ""
    for ch in text:
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
            continue
        depth += (ch == "(") - (ch == ")")
        cur += ch
    out.append(cur)
    return [s.strip() for s in out if s.strip()]


def expand(text):
    """Values of one grid axis: a comma list, where lin(a,b,n) and log(a,b,n) expand to n values
    evenly (geometrically) spaced from a to b."""
    vals = []
    for item in split_values(text):
        low = item.lower()
        if low.startswith(("lin(", "log(")) and low.endswith(")"):
            a, b, n = (s.strip() for s in item[4:-1].split(","))
            a, b, n = float(a), float(b), int(n)
            vals += [float(x) for x in (np.linspace(a, b, n) if low.startswith("lin")
                                        else np.geomspace(a, b, n))]
        else:
            vals.append(item)
    return vals


def fmu_variable(variant, name):
    md = _master.model_description(variant)
    for v in md.modelVariables:
        if v.name == name:
            return v
    return None


def coerce_fmu(variant, name, value):
    v = fmu_variable(variant, name)
    if v.type == "Integer":
        f = float(value)
        if f != int(f):
            raise SystemExit(f"error: {name} is an Integer; {value!r} is not")
        return int(f)
    if v.type == "Boolean":
        return str(value).lower() in ("1", "true", "yes")
    return float(value)


def build_sweep(scene_name, grid, reference=True):
    """Tasks of a sweep: the product of the grid axes (method and H default to the four methods
    and the scene's chart steps); scenes with a fine reference (belt) get one reference task per
    distinct physical setting, which their runs wait for."""
    if scene_name not in SCENES:
        raise SystemExit(f"error: unknown scene {scene_name!r}; known: {', '.join(SCENES)}")
    base = SCENES[scene_name]
    settings = scene_settings(base)
    axes = {}
    for name, values in grid:
        if name in RUN_SETTINGS or name in settings:
            try:
                axes[name] = [coerce_setting(scene_name, name, v) for v in values]
            except ValueError as e:
                raise SystemExit(f"error: {name}: {e}") from None
        else:
            var = fmu_variable(base.variant, name)
            if var is None:
                raise SystemExit(
                    f"error: {name!r} is neither a setting of scene {scene_name} nor a variable of "
                    f"{base.variant}.fmu (./scripts/sweep --list {scene_name} shows both)")
            if var.causality != "parameter":
                raise SystemExit(f"error: {name} is not a parameter of {base.variant}.fmu "
                                 f"(causality {var.causality})")
            axes[name] = [coerce_fmu(base.variant, name, v) for v in values]
    axes.setdefault("method", list(METHODS))
    axes.setdefault("H", list(base.sweep))
    names = list(axes)
    sha = fmu_ref(base.variant)["sha256"]
    tasks, refs = [], {}
    for combo in _product([axes[n] for n in names]):
        point = dict(zip(names, combo))
        method, H = point.pop("method"), point.pop("H")
        sets = {k: v for k, v in point.items() if k in settings}
        fmu = {k: v for k, v in point.items() if k not in settings}
        scene = make_scene(scene_name, sets, fmu)
        needs = None
        if reference and getattr(scene, "fine", None):
            rkey = json.dumps([sets, fmu], sort_keys=True, default=_jsonable)
            if rkey not in refs:
                fm, fH = scene.fine
                refs[rkey] = make_task("reference", scene_name, fm, fH, sets, fmu, base.variant,
                                       sha, cost=run_cost(scene, fm, fH))
                tasks.append(refs[rkey])
            needs = refs[rkey]["spec"]["key"]
        tasks.append(make_task("run", scene_name, method, H, sets, fmu, base.variant, sha,
                               needs=needs, cost=run_cost(scene, method, H)))
    inputs = [n for n in names if n not in RUN_SETTINGS]
    return tasks, inputs


def _product(lists):
    if not lists:
        yield ()
        return
    for head in lists[0]:
        for tail in _product(lists[1:]):
            yield (head,) + tail


def describe(scene_name):
    base = SCENES[scene_name]
    lines = [f"scene {scene_name}: {base.title} ({base.variant}.fmu)",
             f"  runs: method = {', '.join(METHODS)}; H default = "
             + ", ".join(f"{h:g}" for h in base.sweep),
             "  scene settings (NAME=VALUES; tuples as a:b:c):"]
    for k, v in scene_settings(base).items():
        lines.append(f"    {k} = {v!r}")
    lines.append(f"  FMU parameters of {base.variant}.fmu (scene's own values first):")
    own = base.params
    for v in _master.model_description(base.variant).modelVariables:
        if v.causality == "parameter":
            val = own.get(v.name, v.start)
            lines.append(f"    {v.name} = {val}" + ("   (set by the scene)" if v.name in own else ""))
    return "\n".join(lines)


USAGE = """./scripts/sweep SCENE [NAME=VALUES ...] [--scheduler tcp://HOST:PORT | --serial]
                [--workers N] [--out FILE.csv] [--no-reference] [--quiet]
./scripts/sweep --list [SCENE]

NAME=VALUES: a grid axis. NAME is `method`, `H`, a scene setting (e.g. mus, v0, t_end, tol)
or a parameter of the scene's FMU (e.g. friction.muKinetic). VALUES: comma list, lin(a,b,n),
log(a,b,n). The sweep runs the product of the axes (method: the four methods, H: the scene's
chart steps, unless given). Rows go to --out (default out/sweep_SCENE.csv) as they finish;
running the same command again computes only the rows not yet there."""


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="./scripts/sweep", usage=USAGE,
                                 description="Sweeps of the co-simulation scenes on Dask.")
    ap.add_argument("scene", nargs="?")
    ap.add_argument("grid", nargs="*", metavar="NAME=VALUES")
    ap.add_argument("--scheduler", default="local",
                    help="tcp://HOST:PORT of a running Dask scheduler (default: a local cluster)")
    ap.add_argument("--serial", action="store_true", help="run in this process, one after another")
    ap.add_argument("--workers", type=int, default=None,
                    help="worker processes of the local cluster (default: one per core)")
    ap.add_argument("--out", default=None, help="CSV of the rows (default out/sweep_SCENE.csv)")
    ap.add_argument("--no-reference", action="store_true",
                    help="skip the scene's fine reference run (belt: no error2)")
    ap.add_argument("--list", action="store_true", help="list scenes, settings and parameters")
    ap.add_argument("--quiet", action="store_true", help="no per-row lines (the bar only)")
    args = ap.parse_args(argv)
    if args.list:
        for name in ([args.scene] if args.scene else SCENES):
            print(describe(name))
        return 0
    if not args.scene:
        ap.error("a scene is required (one of: " + ", ".join(SCENES) + ")")
    grid = []
    for item in args.grid:
        if "=" not in item:
            ap.error(f"grid axis {item!r} is not NAME=VALUES")
        name, values = item.split("=", 1)
        grid.append((name.strip(), expand(values)))
    tasks, inputs = build_sweep(args.scene, grid, reference=not args.no_reference)
    out = Path(args.out or Path(_master.REPO) / "out" / f"sweep_{args.scene}.csv")
    out.parent.mkdir(parents=True, exist_ok=True)
    where = "serially in this process" if args.serial else (
        "on a local cluster" if args.scheduler == "local" else f"on {args.scheduler}")
    print(f"==> sweep {args.scene}: {len(tasks)} tasks {where}; rows to {out}", flush=True)

    def line(task, row):
        s = task["spec"]
        desc = " ".join(f"{k}={v}" for k, v in {**s["settings"], **s["fmu"]}.items())
        err = (row.get("figures") or {}).get("error")
        what = f"error={err:.3e}" if isinstance(err, float) else ""
        msg = f" {row['status'].upper()}: {row['message']}" if row["status"] != "ok" else ""
        return (f"  {s['kind']:9s} {s['method'] or '':15s} H={s['H']:<8g} {desc} {what}"
                f"  [{row.get('worker', '')}]{msg}")

    t0 = time.monotonic()
    rows = execute(tasks, None if args.serial else args.scheduler, out=out,
                   input_columns=inputs, inputs_of=lambda s: {**s["settings"], **s["fmu"]},
                   log=None if args.quiet else line, workers=args.workers)
    counts = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    print(f"==> {len(rows)} rows ({', '.join(f'{v} {k}' for k, v in sorted(counts.items()))}) "
          f"in {out}; {time.monotonic() - t0:.1f} s", flush=True)
    return 0
