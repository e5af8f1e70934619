#!/usr/bin/env python3
"""Package the co-simulation scenes as SSP 1.0 archives, dist/ssp/<scene>.ssp (belt, bounce,
puck0, bushing_pendulum, chain, chain_damped, engine_mount, engine_mount_damped): the connector
FMUs (dist/<Variant>.fmu), the Body FMU, their parameter sets and connections, generated from the
scene objects of scripts/cosim/scenes.py (scripts/sspkit/systems.py) and the multi-body scenes of
scripts/sspkit/multibody.py, validated against the SSP 1.0 schema (scripts/sspkit/archive.py)
and checked (scripts/sspkit/structure.py).
Run after package.py (it needs dist/*.fmu); docs/ssp.md says what an archive holds.
Usage: package_ssp.py [SCENE ...]   (default: all)
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cosim.connectors import DIST, REPO  # noqa: E402
from sspkit import archive, multibody  # noqa: E402


def main(argv):
    out = DIST / "ssp"
    for name in argv or multibody.ALL:
        system = multibody.system(name)
        path = archive.write(system, out / f"{name}.ssp")
        archive.check(path, system)
        print(f"{str(path.relative_to(REPO)):<36} {path.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main(sys.argv[1:])
