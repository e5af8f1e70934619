#!/usr/bin/env python3
"""Package every variant into dist/fmi3/<Variant>.fmu (FMI 3.0 Co-Simulation, x86_64-linux).

Each FMU holds modelDescription.xml (modelDescription/fmi3/<Variant>.xml with the commit time as
generationDateAndTime), binaries/x86_64-linux/<Variant>.so (the same stripped library as the
FMI 2.0 FMUs: it exports both the fmi2* and the fmi3* functions) and documentation/index.html
generated from the model description. Helpers come from package.py (the FMI 2.0 packager).
Usage: package_fmi3.py [Variant ...]   (default: all five)
"""
import html
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from package import (LIBRARY, REPO, VARIANTS, generation_date, package, page,  # noqa: E402
                     stripped_library)

TYPES = ("Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
         "UInt64", "Boolean", "String", "Binary", "Enumeration", "Clock")

NOT_PROVIDED = """<h2>FMI 3.0 interface</h2>
<p>Co-Simulation only, without Event Mode, clocks or early return: every <code>fmi3DoStep</code>
completes the whole step. Declared and provided: variable communication step size, get/set and
serialize FMU state, directional and adjoint derivatives, variable dependencies. The Model
Exchange and Scheduled Execution functions, Event Mode, clocks, configuration mode and output
derivatives answer <code>fmi3Error</code> with a log message naming the function and why.</p>
"""


def documentation(root: ET.Element) -> str:
    """Short HTML page of an FMI 3.0 model description: model, FMI 3.0 interface, conventions,
    variables."""
    rows = [[var.get("name"), var.get("valueReference"), var.get("causality", "local"),
             var.get("variability", "continuous"), var.tag, var.get("start", ""), var.get("min", ""),
             var.get("max", ""), var.get("unit", ""), var.get("description", "")]
            for var in root.find("ModelVariables") or [] if var.tag in TYPES]
    identity = (f"FMI {html.escape(root.get('fmiVersion', ''))} Co-Simulation FMU, instantiationToken "
                f"<code>{html.escape(root.get('instantiationToken', ''))}</code>.")
    return page(root, identity, NOT_PROVIDED, rows)


def main() -> None:
    variants = sys.argv[1:] or VARIANTS
    unknown = sorted(set(variants) - set(VARIANTS))
    if unknown:
        sys.exit(f"error: unknown variant(s) {', '.join(unknown)}; known: {', '.join(VARIANTS)}")
    if not LIBRARY.is_file():
        sys.exit(f"error: {LIBRARY.relative_to(REPO)} is missing; run cargo build --release")
    out_dir = REPO / "dist" / "fmi3"
    out_dir.mkdir(parents=True, exist_ok=True)
    binary = stripped_library(LIBRARY, REPO / "dist" / "debug")
    date = generation_date()
    for v in variants:
        fmu = package(v, out_dir, [("x86_64-linux", "so", binary)], date,
                      md_dir=REPO / "modelDescription" / "fmi3", doc=documentation)
        print(f"{str(fmu.relative_to(REPO)):<36} {fmu.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main()
