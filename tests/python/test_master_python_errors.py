"""Bad input through the Python bindings (fmi_master): each archive broken in the test, from
dist/ssp's real archives and FMUs, raises fmi_master.MasterError with the same message the
command line prints (master/tests/cli.rs checks those through ./scripts/master): the archive
element, the component, the variable, the FMI function and the time, as far as they apply.
"""
from __future__ import annotations

import io
import zipfile

import pytest

import fmi_master
from conftest import REPO

SSP = REPO / "dist" / "ssp"


def rebuilt(src, dst, edit):
    """A copy of archive `src` at `dst` whose entries {name: bytes} `edit` changes in place."""
    with zipfile.ZipFile(src) as z:
        files = {i.filename: z.read(i.filename) for i in z.infolist()}
    edit(files)
    with zipfile.ZipFile(dst, "w") as z:
        for name, data in files.items():
            z.writestr(name, data)
    return dst


def replace(entry, old, new):
    def edit(files):
        assert old.encode() in files[entry], f"{old!r} not in {entry}"
        files[entry] = files[entry].replace(old.encode(), new.encode())
    return edit


def not_a_library(files):
    """resources/Bushing.fmu with its binary replaced by bytes that are no shared library."""
    with zipfile.ZipFile(io.BytesIO(files["resources/Bushing.fmu"])) as z:
        fmu = {i.filename: z.read(i.filename) for i in z.infolist()}
    fmu["binaries/linux64/Bushing.so"] = b"not a library"
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        for name, data in fmu.items():
            z.writestr(name, data)
    files["resources/Bushing.fmu"] = out.getvalue()


TWO_INTO_ONE = ('  <ssd:Connection startElement="bushing" startConnector="b.f[2]" endElement="pendulum" '
                'endConnector="f[1]"/>\n    </ssd:Connections>')
INT_INTO_REAL = ('  <ssd:Connection startElement="radialthrust" startConnector="event.count" '
                 'endElement="mass" endConnector="f[1]"/>\n    </ssd:Connections>')

CASES = [
    ("malformed SSD", "bounce", replace("SystemStructure.ssd", "</ssd:Elements>", "</ssd:Element>"),
     ["SystemStructure.ssd", "not well-formed XML at line"]),
    ("SSD not SSP 1.0", "bounce",
     replace("SystemStructure.ssd", 'version="1.0" name="bounce"', 'version="2.0" name="bounce"'),
     ["SystemStructure.ssd line 2 <SystemStructureDescription>", "version '2.0' is not SSP 1.0"]),
    ("malformed SSV", "bushing_pendulum", replace("resources/bushing.ssv", "</ssv:Parameters>", ""),
     ["resources/bushing.ssv", "component 'bushing'", "not well-formed XML"]),
    ("SSV value not a number", "bushing_pendulum",
     replace("resources/bushing.ssv", '<ssv:Real value="400.0"/>', '<ssv:Real value="stiff"/>'),
     ["resources/bushing.ssv line", "variable 'elasticity.k1'", "'stiff' is not a number"]),
    ("missing FMU", "bushing_pendulum", lambda f: f.pop("resources/Bushing.fmu"),
     ["<Component>", "component 'bushing'", "the FMU 'resources/Bushing.fmu' is missing from the archive"]),
    ("missing parameter set", "bushing_pendulum", lambda f: f.pop("resources/bushing.ssv"),
     ["<ParameterBinding>", "the parameter set 'resources/bushing.ssv' is missing from the archive"]),
    ("unknown variable in a parameter set", "bushing_pendulum",
     replace("resources/bushing.ssv", 'name="elasticity.k1"', 'name="elasticity.kx"'),
     ["variable 'elasticity.kx'", "the parameter set names a variable resources/Bushing.fmu does not have"]),
    ("two connections into one input", "bushing_pendulum",
     replace("SystemStructure.ssd", "</ssd:Connections>", TWO_INTO_ONE),
     ["component 'pendulum'", "variable 'f[1]'", "two connections lead into this input"]),
    ("type mismatch", "bounce", replace("SystemStructure.ssd", "</ssd:Connections>", INT_INTO_REAL),
     ["radialthrust.event.count (Int32) to mass.f[1] (Float64): the types differ"]),
    ("zip entry leaving the folder", "bounce", lambda f: f.__setitem__("../../escaped.txt", b"x"),
     ["the zip entry '../../escaped.txt' would leave the extraction folder"]),
    ("FMU that fails to load", "bushing_pendulum", not_a_library,
     ["resources/Bushing.fmu", "component 'bushing'", "cannot load"]),
]


@pytest.mark.parametrize("what,scene,edit,pieces", CASES, ids=[c[0] for c in CASES])
def test_bad_input_raises_the_masters_message(tmp_path, what, scene, edit, pieces):
    src = SSP / f"{scene}.ssp"
    if not src.exists():
        pytest.fail(f"{src.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)
    path = rebuilt(src, tmp_path / f"{scene}.ssp", edit)
    with pytest.raises(fmi_master.MasterError) as e:
        fmi_master.simulate(str(path), step=1e-3, stop=0.01)
    message = str(e.value)
    for piece in pieces:
        assert piece in message, f"{what}: {piece!r} not in {message!r}"
    assert "\n" not in message.strip(), f"{what}: one message, not several: {message!r}"
    assert not (tmp_path.parent / "escaped.txt").exists()
