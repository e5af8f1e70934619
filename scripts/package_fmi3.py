#!/usr/bin/env python3
"""Package every model into dist/fmi3/<Model>.fmu (FMI 3.0 Co-Simulation, x86_64-linux): the
five connector variants and the Body.

Each FMU holds modelDescription.xml (the crate's modelDescription/fmi3/<Model>.xml with the
commit time as generationDateAndTime), binaries/x86_64-linux/<Model>.so (the same stripped
library as the FMI 2.0 FMU: it exports both the fmi2* and the fmi3* functions) and
documentation/index.html generated from the model description. Helpers come from package.py
(the FMI 2.0 packager).
Usage: package_fmi3.py [Model ...]   (default: all six)
"""
import html
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from package import (REPO, crate_of, generation_date, package, page, selected,  # noqa: E402
                     stripped_library)

TYPES = ("Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
         "UInt64", "Boolean", "String", "Binary", "Enumeration", "Clock")

# What the FMI 3.0 interface of each crate's FMUs offers, for the documentation page.
CONNECTOR_INTERFACE = """<h2>FMI 3.0 interface</h2>
<p>Co-Simulation only, without Event Mode, clocks or early return: every <code>fmi3DoStep</code>
completes the whole step. Declared and provided: variable communication step size, get/set and
serialize FMU state, directional and adjoint derivatives, variable dependencies. The Model
Exchange and Scheduled Execution functions, Event Mode, clocks, configuration mode and output
derivatives answer <code>fmi3Error</code> with a log message naming the function and why.</p>
"""
BODY_INTERFACE = """<h2>FMI 3.0 interface</h2>
<p>Co-Simulation only, without Event Mode, clocks or early return: every <code>fmi3DoStep</code>
completes the whole step. Declared and provided: variable communication step size, get/set and
serialize FMU state, variable dependencies (outputs depend on the parameters in Initialization
Mode and on nothing after it: no direct feedthrough). No directional or adjoint derivatives. The
Model Exchange and Scheduled Execution functions, Event Mode, clocks, configuration mode,
derivatives and output derivatives answer <code>fmi3Error</code> with a log message naming the
function and why.</p>
"""
INTERFACE = {"connector_fmu": CONNECTOR_INTERFACE, "body_fmu": BODY_INTERFACE}


def documentation(root: ET.Element) -> str:
    """Short HTML page of an FMI 3.0 model description: model, FMI 3.0 interface, conventions,
    variables."""
    rows = [[var.get("name"), var.get("valueReference"), var.get("causality", "local"),
             var.get("variability", "continuous"), var.tag, var.get("start", ""), var.get("min", ""),
             var.get("max", ""), var.get("unit", ""), var.get("description", "")]
            for var in root.find("ModelVariables") or [] if var.tag in TYPES]
    identity = (f"FMI {html.escape(root.get('fmiVersion', ''))} Co-Simulation FMU, instantiationToken "
                f"<code>{html.escape(root.get('instantiationToken', ''))}</code>.")
    return page(root, identity, INTERFACE[crate_of(root.get("modelName", "")).name], rows)


def main() -> None:
    out_dir = REPO / "dist" / "fmi3"
    out_dir.mkdir(parents=True, exist_ok=True)
    date = generation_date()
    for crate, models in selected(sys.argv[1:]):
        binary = stripped_library(crate.library, REPO / "dist" / "debug")
        for m in models:
            fmu = package(m, out_dir, [("x86_64-linux", "so", binary)], date, fmi3=True,
                          doc=documentation)
            print(f"{str(fmu.relative_to(REPO)):<36} {fmu.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main()
