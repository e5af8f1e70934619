#!/usr/bin/env python3
"""Package the co-simulation scenes as SSP 1.0 archives, dist/ssp/<scene>.ssp (belt, bounce,
puck0, bushing_pendulum, chain, chain_damped, engine_mount, engine_mount_damped): the connector
FMUs (dist/<Variant>.fmu), the Body FMU, their parameter sets and connections, generated from the
scene objects of scripts/cosim/scenes.py (scripts/sspkit/systems.py) and the multi-body scenes of
scripts/sspkit/multibody.py, validated against the SSP 1.0 schema (scripts/sspkit/archive.py)
and checked (scripts/sspkit/structure.py).
Run after package.py (it needs dist/*.fmu); docs/ssp.md says what an archive holds.
Usage: package_ssp.py [--extrapolation E] [--out DIR] [SCENE ...]   (default: all scenes, every
connector at systems.EXTRAPOLATION, into dist/ssp; --extrapolation 0 gives the held-input
archives docs/ssp.md compares them with)
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cosim.connectors import DIST, REPO  # noqa: E402
from sspkit import archive, multibody  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", metavar="SCENE", help=f"one of {', '.join(multibody.ALL)}")
    ap.add_argument("--extrapolation", type=int, choices=(0, 1, 2, 3),
                    help="every connector's cosim.extrapolation (default: systems.EXTRAPOLATION)")
    ap.add_argument("--out", type=Path, default=DIST / "ssp", help="where the archives go (default dist/ssp)")
    args = ap.parse_args(argv)
    unknown = [n for n in args.scenes if n not in multibody.ALL]
    if unknown:
        ap.error(f"no scene {', '.join(map(repr, unknown))}; there are: {', '.join(multibody.ALL)}")
    for name in args.scenes or multibody.ALL:
        system = multibody.system(name, args.extrapolation)
        path = archive.write(system, args.out / f"{name}.ssp")
        archive.check(path, system)
        print(f"{shown(path):<36} {path.stat().st_size:>12,d} bytes")


def shown(path):
    """`path` relative to the repository where it is inside it."""
    try:
        return str(path.resolve().relative_to(REPO))
    except ValueError:
        return str(path)


if __name__ == "__main__":
    main(sys.argv[1:])
