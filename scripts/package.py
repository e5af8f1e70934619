#!/usr/bin/env python3
"""Package every variant into dist/<Variant>.fmu (FMI 2.0 Co-Simulation, linux64).

Each FMU holds modelDescription.xml (modelDescription/<Variant>.xml with the commit time as
generationDateAndTime), binaries/linux64/<Variant>.so (target/release/libconnector_fmu.so with
its debug information and symbol table stripped) and documentation/index.html generated from
the model description. The debug information stays beside the FMUs for developers, in
dist/debug/connector_fmu.so.debug (gdb finds it through the binary's .gnu_debuglink).
Usage: package.py [Variant ...]   (default: all five)
"""
import html
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
VARIANTS = ["Planar", "ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing", "RadialThrust"]
LIBRARY = REPO / "target" / "release" / "libconnector_fmu.so"
DEBUG_FILE = "connector_fmu.so.debug"
TYPES = ("Real", "Integer", "Boolean", "String", "Enumeration")

CONVENTIONS = """<h2>Conventions</h2>
<p>SI units throughout; angles in radians. Node orientations are unit quaternions, scalar first
(<code>q.w, q.x, q.y, q.z</code>), mapping node-local coordinates to the world frame; the FMU
normalises them. Positions, velocities and angular velocities of the nodes are given in the world
frame. Node loads (<code>a.f, a.m, b.f, b.m</code>) are what the connector exerts <em>on</em> the
node, in the world frame, moments about the node's own position. Connector components follow
Abaqus numbering: 1&ndash;3 translations, 4&ndash;6 rotations (ur1 = component 4).</p>
"""


HEADINGS = ("name", "valueReference", "causality", "variability", "type", "start", "min", "max", "unit",
            "description")


def page(root: ET.Element, identity: str, interface: str, rows: list[list[str]]) -> str:
    """The documentation page of either FMI version: model name and description, `identity`
    (the FMI version and GUID or token line), `interface` (HTML, may be empty), the conventions
    and the variable table (`rows`, one list of cells per variable in HEADINGS order)."""
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
{interface}{CONVENTIONS}<h2>Variables</h2>
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
    the debug information is written to debug_dir for developers, linked by .gnu_debuglink."""
    debug_dir.mkdir(parents=True, exist_ok=True)
    debug = debug_dir / DEBUG_FILE
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
            md_dir: Path = REPO / "modelDescription", doc=None) -> Path:
    """Writes out_dir/<variant>.fmu: the model description of `md_dir` (dated), each binary as
    binaries/<platform>/<modelIdentifier>.<ext> (`binaries`: (platform, ext, bytes)), and the
    documentation page `doc(root)` (default: the FMI 2.0 page)."""
    xml_path = md_dir / f"{variant}.xml"
    if not xml_path.is_file():
        sys.exit(f"error: {xml_path.relative_to(REPO)} is missing; generate it with\n"
                 "  cargo run --release --bin gen_model_description -- modelDescription")
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
    variants = sys.argv[1:] or VARIANTS
    unknown = sorted(set(variants) - set(VARIANTS))
    if unknown:
        sys.exit(f"error: unknown variant(s) {', '.join(unknown)}; known: {', '.join(VARIANTS)}")
    if not LIBRARY.is_file():
        sys.exit(f"error: {LIBRARY.relative_to(REPO)} is missing; run cargo build --release")
    out_dir = REPO / "dist"
    out_dir.mkdir(exist_ok=True)
    binary = stripped_library(LIBRARY, out_dir / "debug")
    date = generation_date()
    for v in variants:
        fmu = package(v, out_dir, [("linux64", "so", binary)], date)
        print(f"{str(fmu.relative_to(REPO)):<36} {fmu.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main()
