#!/usr/bin/env python3
"""Package every model into dist/<Model>.fmu (FMI 2.0 Co-Simulation, linux64): the five
connector variants (crate connector_fmu) and the Body (crate body_fmu, bodies/).

Each FMU holds modelDescription.xml (the crate's committed modelDescription/<Model>.xml with
the commit time as generationDateAndTime), binaries/linux64/<Model>.so (the crate's
target/release/lib<crate>.so with its debug information and symbol table stripped) and
documentation/index.html generated from the model description. The debug information stays
beside the FMUs for developers, in dist/debug/<crate>.so.debug (gdb finds it through the
binary's .gnu_debuglink).
Usage: package.py [Model ...]   (default: all six)
"""
import html
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
VARIANTS = ["Planar", "ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing", "RadialThrust"]
TYPES = ("Real", "Integer", "Boolean", "String", "Enumeration")

CONVENTIONS = """<h2>Conventions</h2>
<p>SI units throughout; angles in radians. Node orientations are unit quaternions, scalar first
(<code>q.w, q.x, q.y, q.z</code>), mapping node-local coordinates to the world frame; the FMU
normalises them. Positions, velocities and angular velocities of the nodes are given in the world
frame. Node loads (<code>a.f, a.m, b.f, b.m</code>) are what the connector exerts <em>on</em> the
node, in the world frame, moments about the node's own position. Connector components follow
Abaqus numbering: 1&ndash;3 translations, 4&ndash;6 rotations (ur1 = component 4).</p>
"""


BODY_CONVENTIONS = """<h2>Conventions</h2>
<p>SI units throughout; angles in radians. The orientation is a unit quaternion, scalar first
(<code>q.w, q.x, q.y, q.z</code>), mapping body coordinates to the world frame; positions,
velocities, the angular velocity, gravity and the load inputs (<code>f</code>: force at the centre
of mass, <code>m</code>: moment about it) are in the world frame. Over each communication step
the load set before the step is held, as the project's zero-order-hold master holds it: model 0
moves along and about world axes, each exactly; model 1 is a free rigid body, classical RK4 in
substeps that turn it by at most <code>rigid.maxTurn</code>. To couple it to a connector FMU,
connect the connector's <code>b.f[i]</code>, <code>b.m[i]</code> to <code>f[i]</code>,
<code>m[i]</code> and <code>r, q, v, w</code> to its node inputs <code>b.r[i]</code>,
<code>b.q.*</code>, <code>b.v[i]</code>, <code>b.w[i]</code> (or node a's).</p>
"""


@dataclass(frozen=True)
class Crate:
    """A crate of the workspace whose one library serves the FMUs of `models` (the GUID passed to
    Instantiate selects the model)."""
    name: str                 # the library: target/release/lib<name>.so
    models: tuple[str, ...]
    md_dir: Path              # committed FMI 2.0 model descriptions; FMI 3.0 ones in md_dir/fmi3
    generator: str            # the binary that writes them
    conventions: str          # the documentation page's Conventions section (HTML)

    @property
    def library(self) -> Path:
        return REPO / "target" / "release" / f"lib{self.name}.so"


CRATES = (
    Crate("connector_fmu", tuple(VARIANTS), REPO / "modelDescription", "gen_model_description",
          CONVENTIONS),
    Crate("body_fmu", ("Body",), REPO / "bodies" / "modelDescription", "gen_body_model_description",
          BODY_CONVENTIONS),
)
MODELS = [m for c in CRATES for m in c.models]


def crate_of(model: str) -> Crate:
    return next(c for c in CRATES if model in c.models)


def selected(args: list[str]) -> list[tuple[Crate, list[str]]]:
    """The crates and their models named in `args` (every model when empty), each crate's
    library checked to be built; exits naming what is unknown or missing."""
    unknown = sorted(set(args) - set(MODELS))
    if unknown:
        sys.exit(f"error: unknown model(s) {', '.join(unknown)}; known: {', '.join(MODELS)}")
    chosen = [(c, [m for m in c.models if not args or m in args]) for c in CRATES]
    chosen = [(c, ms) for c, ms in chosen if ms]
    for c, _ in chosen:
        if not c.library.is_file():
            sys.exit(f"error: {c.library.relative_to(REPO)} is missing; run cargo build --release")
    return chosen


HEADINGS = ("name", "valueReference", "causality", "variability", "type", "start", "min", "max", "unit",
            "description")


def page(root: ET.Element, identity: str, interface: str, rows: list[list[str]]) -> str:
    """The documentation page of either FMI version: model name and description, `identity`
    (the FMI version and GUID or token line), `interface` (HTML, may be empty), the model's
    conventions and the variable table (`rows`, one list of cells per variable in HEADINGS
    order)."""
    name = html.escape(root.get("modelName", ""))
    head = "".join(f"<th>{h}</th>" for h in HEADINGS)
    body = "\n".join("<tr>" + "".join(f"<td>{html.escape(c or '')}</td>" for c in r) + "</tr>" for r in rows)
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{name}</title>
<style>body{{font-family:sans-serif}} table{{border-collapse:collapse}} td,th{{border:1px solid #999;padding:2px 6px}}</style>
</head><body>
<h1>{name}</h1>
<p>{html.escape(root.get("description", ""))}</p>
<p>{identity}</p>
{interface}{crate_of(root.get("modelName", "")).conventions}<h2>Variables</h2>
<table>
<tr>{head}</tr>
{body}
</table>
</body></html>
"""


def documentation(root: ET.Element) -> str:
    """Short HTML page of an FMI 2.0 model description: model, conventions, variables."""
    units = {t.get("name"): t[0].get("unit", "") for t in root.iterfind("TypeDefinitions/SimpleType") if len(t)}
    rows = []
    for sv in root.iterfind("ModelVariables/ScalarVariable"):
        typ = next((c for c in sv if c.tag in TYPES), None)
        get = typ.get if typ is not None else (lambda _k, d="": d)
        unit = get("unit") or (units.get(get("declaredType"), "") if typ is not None else "")
        rows.append([sv.get("name"), sv.get("valueReference"), sv.get("causality", "local"),
                     sv.get("variability", "continuous"), typ.tag if typ is not None else "",
                     get("start", ""), get("min", ""), get("max", ""), unit, sv.get("description", "")])
    identity = (f"FMI {html.escape(root.get('fmiVersion', ''))} Co-Simulation FMU, GUID "
                f"<code>{html.escape(root.get('guid', ''))}</code>.")
    return page(root, identity, "", rows)


def generation_date() -> str | None:
    """The commit time of HEAD in UTC (ISO 8601), so that packaging the same commit gives the
    same FMU; SOURCE_DATE_EPOCH overrides it; None outside a git checkout."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch is None:
        try:
            epoch = subprocess.run(["git", "log", "-1", "--format=%ct"], cwd=REPO, check=True,
                                   capture_output=True, text=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return None
    if not epoch:
        return None
    import datetime
    t = datetime.datetime.fromtimestamp(int(epoch), tz=datetime.timezone.utc)
    return t.strftime("%Y-%m-%dT%H:%M:%SZ")


def with_generation_date(xml: bytes, date: str | None) -> bytes:
    """The model description with generationDateAndTime on its root element."""
    if date is None:
        return xml
    text = xml.decode("utf-8")
    text, n = re.subn(r"<fmiModelDescription\b", f'<fmiModelDescription generationDateAndTime="{date}"',
                      text, count=1)
    if n != 1:
        sys.exit("error: no fmiModelDescription element to date")
    return text.encode("utf-8")


def stripped_library(library: Path, debug_dir: Path) -> bytes:
    """The library without debug information and symbol table (its exports stay in .dynsym);
    the debug information is written to debug_dir for developers (<crate>.so.debug), linked by
    .gnu_debuglink."""
    debug_dir.mkdir(parents=True, exist_ok=True)
    debug = debug_dir / f"{library.stem.removeprefix('lib')}.so.debug"
    subprocess.run(["objcopy", "--only-keep-debug", str(library), str(debug)], check=True)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / library.name
        subprocess.run(["objcopy", "--strip-all", f"--add-gnu-debuglink={debug}", str(library), str(out)],
                       check=True, cwd=debug_dir)
        return out.read_bytes()


def add(zf: zipfile.ZipFile, arcname: str, data: bytes, mode: int = 0o644) -> None:
    info = zipfile.ZipInfo(arcname, date_time=(1980, 1, 1, 0, 0, 0))  # reproducible archives
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = mode << 16
    zf.writestr(info, data)


def package(variant: str, out_dir: Path, binaries: list[tuple[str, str, bytes]], date: str | None,
            fmi3: bool = False, doc=None) -> Path:
    """Writes out_dir/<variant>.fmu: the crate's committed model description (FMI 3.0 with
    `fmi3`; dated), each binary as binaries/<platform>/<modelIdentifier>.<ext> (`binaries`:
    (platform, ext, bytes)), and the documentation page `doc(root)` (default: the FMI 2.0 page)."""
    crate = crate_of(variant)
    xml_path = (crate.md_dir / "fmi3" if fmi3 else crate.md_dir) / f"{variant}.xml"
    if not xml_path.is_file():
        sys.exit(f"error: {xml_path.relative_to(REPO)} is missing; generate it with\n"
                 f"  cargo run --release --bin {crate.generator}")
    xml = with_generation_date(xml_path.read_bytes(), date)
    root = ET.fromstring(xml)
    cs = root.find("CoSimulation")
    identifier = cs.get("modelIdentifier") if cs is not None else None
    if identifier != variant:
        sys.exit(f"error: {xml_path.name}: CoSimulation modelIdentifier is {identifier!r}, expected {variant!r}")
    fmu = out_dir / f"{variant}.fmu"
    tmp = fmu.with_suffix(".fmu.tmp")
    with zipfile.ZipFile(tmp, "w") as zf:
        add(zf, "modelDescription.xml", xml)
        for platform, ext, blob in binaries:
            add(zf, f"binaries/{platform}/{identifier}.{ext}", blob, 0o755)
        add(zf, "documentation/index.html", (doc or documentation)(root).encode("utf-8"))
    tmp.replace(fmu)
    return fmu


def main() -> None:
    out_dir = REPO / "dist"
    out_dir.mkdir(exist_ok=True)
    date = generation_date()
    for crate, models in selected(sys.argv[1:]):
        binary = stripped_library(crate.library, out_dir / "debug")
        for m in models:
            fmu = package(m, out_dir, [("linux64", "so", binary)], date)
            print(f"{str(fmu.relative_to(REPO)):<36} {fmu.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main()
