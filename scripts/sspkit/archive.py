"""A system (systems.py) as an SSP 1.0 archive, and the checks of an archive made before a run.

`write(system, path)` writes <scene>.ssp: SystemStructure.ssd (one ssd:Component per FMU with the
ssd:Connectors it uses and a ssd:ParameterBinding to its parameter set, the connections, a
DefaultExperiment over the scene's t_end), resources/<component>.ssv (one ssv:ParameterSet per
component, all named systems.PARAMETER_SET) and resources/<Model>.fmu (dist/ copies). The SSD and
SSV files are made with pyssp-standard and validated against the SSP 1.0 schema it ships
(`validate`). The zip entries carry fixed dates, and the SSD the commit time, so the same commit
packages the same archive.

`check(path, system)` reads an archive back and refuses, with a message naming what is wrong,
what structure.py finds (using the archive's own FMUs: a connection whose endpoint is not a
variable of that causality, two connections into one input, a parameter that names no parameter
of the FMU) and a parameter or connection the scene needs that the archive leaves out or sets
differently: libcosim only warns about a parameter it cannot apply, and an omitted one would
silently keep the FMU's default.

Uses pyssp_standard, lxml (via it), xmlschema, structure.py and systems.py; package.py for the
reproducible zip entries and the commit date.
"""
from __future__ import annotations

import tempfile
import zipfile
from pathlib import Path

import xmlschema
from lxml import etree as ET
from pyssp_standard import SSD, SSV
from pyssp_standard.common_content_ssc import (Annotation, TypeBoolean, TypeInteger, TypeReal)
from pyssp_standard.ssd import (Component as SSDComponent, Connection, Connector,
                                DefaultExperiment, ParameterBinding, System as SSDSystem)
from pyssp_standard.standard import ModelicaStandard

import package
from cosim.connectors import DIST

from . import structure, systems

SSD_NAME = "SystemStructure.ssd"
FMU_TYPE = "application/x-fmu-sharedlibrary"
SCHEMAS = {"ssd": ModelicaStandard.schemas["ssd"], "ssv": ModelicaStandard.schemas["ssv"]}
TYPES = {"Real": TypeReal, "Integer": TypeInteger, "Boolean": TypeBoolean}
OSP = "https://opensimulationplatform.com/SSP/1.0"     # libcosim's annotation: the base step
NS = {k: ModelicaStandard.namespaces[k] for k in ("ssd", "ssv", "ssc")}
GENERATOR = "connector-fmu scripts/package_ssp.py (pyssp-standard)"


# An archive that does not fit its FMUs or its scene; the message says where (one class with
# structure.py's, so that a caller catches both).
ArchiveError = structure.StructureError


def text(value):
    """A parameter value as SSV text: Python's shortest repr (it reads back to the same double),
    XML Schema booleans."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def connector_kinds(system):
    """{component: {variable: kind}} of the SSD connectors: every connected variable and every
    parameter set, with the causality its FMU gives it."""
    out = {}
    for comp in system.components:
        vs = systems.variables(comp.model)
        used = [v for s, o, e, i in system.connections for c, v in ((s, o), (e, i)) if c == comp.name]
        names = list(dict.fromkeys(used + list(comp.params)))
        out[comp.name] = {n: vs[n].causality for n in names if n in vs}
        missing = [n for n in names if n not in vs]
        if missing:
            raise ArchiveError(f"{comp.name} ({comp.model}.fmu) has no variable {', '.join(missing)}")
    return out


def ssc_type(name):
    """The ssc type element of an FMU variable type (no unit)."""
    return TypeReal(None) if name == "Real" else TYPES[name]()


def ssd_system(system, kinds):
    """The ssd:System of `system` (pyssp-standard objects)."""
    top = SSDSystem(name=system.name)
    for comp in system.components:
        vs = systems.variables(comp.model)
        c = SSDComponent()
        c.name, c.component_type, c.source = comp.name, FMU_TYPE, f"resources/{comp.model}.fmu"
        c.connectors = [Connector(name=n, kind=k, type_=ssc_type(vs[n].type))
                        for n, k in kinds[comp.name].items()]
        c.parameter_bindings = [ParameterBinding(source=f"resources/{comp.name}.ssv")]
        top.elements.append(c)
    top.connections = [Connection(start_element=s, start_connector=o, end_element=e, end_connector=i)
                       for s, o, e, i in system.connections]
    return top


def write_ssd(system, path, step=1e-3, date=None):
    """SystemStructure.ssd of `system` at `path`; `step`: the base step libcosim reads from the
    DefaultExperiment's annotation (a master may use another)."""
    kinds = connector_kinds(system)
    with SSD(path, mode="w") as ssd:
        ssd.name, ssd.version = system.name, "1.0"
        ssd.top_level_metadata.generationTool = GENERATOR
        ssd.top_level_metadata.generationDateAndTime = date or ""
        ssd.system = ssd_system(system, kinds)
        exp = DefaultExperiment()
        exp.start_time, exp.stop_time = 0.0, float(system.scene.t_end)
        # the osp prefix is declared on the annotation: libcosim reads osp:Algorithm's children
        # as algorithms, and an xmlns attribute there would be one
        note = Annotation(ET.Element(f"{{{NS['ssc']}}}Annotation", type="com.opensimulationplatform",
                                     nsmap={"osp": OSP}))
        ET.SubElement(ET.SubElement(note.root, f"{{{OSP}}}Algorithm"), f"{{{OSP}}}FixedStepAlgorithm",
                      baseStepSize=repr(step))
        exp.annotations.add_annotation(note)
        ssd.default_experiment = exp
    return path


def write_ssv(comp, path):
    """resources/<component>.ssv: the component's parameter values, typed as its FMU types them."""
    vs = systems.variables(comp.model)
    with SSV(path, mode="w") as ssv:
        ssv.ssv_elem.name = systems.PARAMETER_SET    # (the proxy property does not reach it)
        for name, value in comp.params.items():
            ssv.add_parameter(name, vs[name].type, value=text(value))
            # pyssp-standard 0.9.1 keeps unit=None on a Real without unit, which lxml refuses
            ssv.parameters[-1]["type_value"].parameter.pop("unit", None)
    return path


def validate(path, kind):
    """Validate an SSD ('ssd') or SSV ('ssv') file against the SSP 1.0 XSD pyssp-standard ships
    (xmlschema); raises xmlschema.XMLSchemaValidationError naming the element."""
    xmlschema.validate(str(path), xmlschema.XMLSchema10(str(SCHEMAS[kind])))


def write(system, path, step=1e-3, dist=DIST):
    """Write the archive of `system` to `path` (validated); returns the path."""
    path = Path(path)
    date = package.generation_date()
    with tempfile.TemporaryDirectory(prefix="ssp-") as tmp:
        tmp = Path(tmp)
        files = {SSD_NAME: write_ssd(system, tmp / SSD_NAME, step, date)}
        validate(files[SSD_NAME], "ssd")
        for comp in system.components:
            ssv = write_ssv(comp, tmp / f"{comp.name}.ssv")
            validate(ssv, "ssv")
            files[f"resources/{comp.name}.ssv"] = ssv
        for model in dict.fromkeys(c.model for c in system.components):
            files[f"resources/{model}.fmu"] = Path(dist) / f"{model}.fmu"
        path.parent.mkdir(parents=True, exist_ok=True)
        part = path.with_suffix(".ssp.tmp")
        with zipfile.ZipFile(part, "w") as zf:
            for arcname, src in files.items():
                package.add(zf, arcname, Path(src).read_bytes())
        part.replace(path)
    return path


# --- reading an archive back, and the checks before a run -------------------------------------


def read(path):
    """(components, connections) of an archive: components {name: (model, {param: text})},
    connections [(start element, output, end element, input)]."""
    with zipfile.ZipFile(path) as zf:
        root = ET.fromstring(zf.read(SSD_NAME))
        comps = {}
        for c in root.iterfind("ssd:System/ssd:Elements/ssd:Component", NS):
            model = Path(c.get("source")).stem
            params = {}
            for b in c.iterfind("ssd:ParameterBindings/ssd:ParameterBinding", NS):
                ssv = ET.fromstring(zf.read(b.get("source")))
                for p in ssv.iterfind("ssv:Parameters/ssv:Parameter", NS):
                    params[p.get("name")] = p[0].get("value")
            comps[c.get("name")] = (model, params)
        conns = [(c.get("startElement"), c.get("startConnector"), c.get("endElement"), c.get("endConnector"))
                 for c in root.iterfind("ssd:System/ssd:Connections/ssd:Connection", NS)]
    return comps, conns


def check(path, system):
    """Refuse (ArchiveError, every problem listed) an archive whose connections or parameters do
    not fit its FMUs (structure.problems), or whose parameter values and connections are not
    the scene's (`system`)."""
    problems = structure.problems(path)
    comps, conns = read(path)
    for comp in system.components:
        have = comps.get(comp.name, (None, {}))[1]
        for p, value in comp.params.items():
            if p not in have:
                problems.append(f"{comp.name}: parameter {p} (scene {system.name}: {text(value)}) is missing")
            elif have[p] != text(value):
                problems.append(f"{comp.name}: parameter {p} = {have[p]}, scene {system.name} needs {text(value)}")
    want = set(system.connections)
    for c in sorted(want - set(conns)):
        problems.append(f"connection {c[0]}.{c[1]} -> {c[2]}.{c[3]} of scene {system.name} is missing")
    if problems:
        raise ArchiveError(f"{path}:\n  " + "\n  ".join(problems))
