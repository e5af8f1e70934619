"""Any SSP archive read back as its structure, and the problems that make it unable to work,
found before a tool runs it: every check uses the FMUs inside the archive (their
modelDescription.xml, FMI 2.0 or 3.0), not dist/, so it applies to a user's own archive.

  read(path)       Archive: the system's name, its components {name: Element(model source,
                   {parameter: value text})}, its connections, and each FMU's variables
  problems(path)   one line per problem, naming the connection or the element:
                   - a component whose FMU is not in the archive,
                   - a connection whose endpoint names no variable of that FMU,
                   - a connection from a variable that is not an output (or a parameter) or into
                     one that is not an input (an output connected to an output),
                   - two or more connections into one input,
                   - a parameter set naming a variable the FMU does not have, or one that is no
                     parameter; an ssd:Connector naming no variable of the FMU

libcosim refuses a second connection into one input, Ecos keeps the last one silently; both
only warn about a parameter they cannot apply (docs/ssp.md, "Broken archives"). Uses zipfile
and lxml only.
"""
from __future__ import annotations

import io
import zipfile
from dataclasses import dataclass, field
from pathlib import PurePosixPath

from lxml import etree as ET

SSD_NAME = "SystemStructure.ssd"
NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
      "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues"}
FMI3_TYPES = {"Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
              "UInt64", "Boolean", "String", "Binary", "Enumeration", "Clock"}


@dataclass
class Variable:
    name: str
    causality: str
    type: str


@dataclass
class Element:
    """A component: its FMU's entry in the archive, the model's name (the file's stem) and its
    parameter values as the parameter sets write them."""
    source: str
    params: dict = field(default_factory=dict)
    connectors: list = field(default_factory=list)     # the ssd:Connector names it declares

    @property
    def model(self):
        return PurePosixPath(self.source).stem


@dataclass
class Archive:
    name: str
    components: dict
    connections: list            # (start element, start connector, end element, end connector)
    variables: dict              # source → {name: Variable}, or None when the FMU is absent
    parameter_sets: list = field(default_factory=list)   # the ssv:ParameterSet names, in order


class StructureError(ValueError):
    """An archive that cannot work; the message lists every problem, one per line."""


def fmu_variables(fmu_bytes):
    """{name: Variable} of an FMU (its modelDescription.xml, FMI 2.0 or 3.0)."""
    with zipfile.ZipFile(io.BytesIO(fmu_bytes)) as fz:
        root = ET.fromstring(fz.read("modelDescription.xml"))
    out = {}
    mv = root.find("ModelVariables")
    for v in (mv if mv is not None else []):
        if not isinstance(v.tag, str):
            continue
        if v.tag == "ScalarVariable":                                  # FMI 2.0
            kind = next((c.tag for c in v if isinstance(c.tag, str)), "Real")
        elif v.tag in FMI3_TYPES:
            kind = v.tag
        else:
            continue
        out[v.get("name")] = Variable(v.get("name"), v.get("causality", "local"), kind)
    return out


def read(path):
    """The Archive at `path` (a zip holding SystemStructure.ssd)."""
    with zipfile.ZipFile(path) as zf:
        names = set(zf.namelist())
        root = ET.fromstring(zf.read(SSD_NAME))
        system = root.find("ssd:System", NS)
        comps, variables, sets = {}, {}, []
        for c in system.iterfind("ssd:Elements/ssd:Component", NS):
            el = Element(c.get("source"))
            for b in c.iterfind("ssd:ParameterBindings/ssd:ParameterBinding", NS):
                src = b.get("source")
                if src is None or src not in names:
                    continue
                ssv = ET.fromstring(zf.read(src))
                if ssv.get("name") not in sets:
                    sets.append(ssv.get("name"))
                for p in ssv.iterfind("ssv:Parameters/ssv:Parameter", NS):
                    el.params[p.get("name")] = p[0].get("value") if len(p) else None
            el.connectors = [k.get("name") for k in c.iterfind("ssd:Connectors/ssd:Connector", NS)]
            comps[c.get("name")] = el
            if el.source not in variables:
                variables[el.source] = fmu_variables(zf.read(el.source)) if el.source in names else None
        conns = [(c.get("startElement"), c.get("startConnector"), c.get("endElement"), c.get("endConnector"))
                 for c in system.iterfind("ssd:Connections/ssd:Connection", NS)]
    return Archive(system.get("name"), comps, conns, variables, sets)


def text(c):
    return f"connection {c[0]}.{c[1]} -> {c[2]}.{c[3]}"


def problems(path):
    """Every problem of the archive at `path` that keeps it from working, one line each (empty:
    none found)."""
    a = read(path)
    out = []
    for name, el in a.components.items():
        if a.variables[el.source] is None:
            out.append(f"{name}: its FMU {el.source} is not in the archive")
    feeds = {}
    for c in a.connections:
        for comp, var, want in ((c[0], c[1], ("output", "parameter", "calculatedParameter")), (c[2], c[3], ("input",))):
            el = a.components.get(comp)
            if el is None:
                out.append(f"{text(c)}: no component {comp!r}")
                continue
            vs = a.variables[el.source]
            if vs is None:
                continue
            v = vs.get(var)
            if v is None:
                out.append(f"{text(c)}: {el.model}.fmu has no variable {var!r}")
            elif v.causality not in want:
                out.append(f"{text(c)}: {var!r} of {el.model}.fmu is an {v.causality}, not an {want[0]}")
        feeds.setdefault((c[2], c[3]), []).append(c)
    for (comp, var), cs in feeds.items():
        if len(cs) > 1:
            sources = ", ".join(f"{s}.{o}" for s, o, _, _ in cs)
            out.append(f"input {comp}.{var} has {len(cs)} connections into it ({sources}); an input takes "
                       f"one: give each load its own input (a Body's ports, docs/body.md)")
    for name, el in a.components.items():
        vs = a.variables[el.source]
        if vs is None:
            continue
        for k in el.connectors:
            if k not in vs:
                out.append(f"{name}: declares the connector {k!r}, which is no variable of {el.model}.fmu")
        for p in el.params:
            v = vs.get(p)
            if v is None or v.causality != "parameter":
                out.append(f"{name}: the parameter set names {p!r}, which is no parameter of {el.model}.fmu")
    return out


def check(path):
    """Raise StructureError listing the problems of the archive at `path`, if any."""
    found = problems(path)
    if found:
        raise StructureError(f"{path}:\n  " + "\n  ".join(found))
    return read(path)
