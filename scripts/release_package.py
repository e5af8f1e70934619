#!/usr/bin/env python3
"""Package the release FMUs: dist/release/<Variant>.fmu with binaries for linux64 (glibc 2.17),
win64 and darwin64 (universal x86_64 + arm64), all from one library per platform that
scripts/release built (already stripped at link time).

Usage: release_package.py <linux .so> <windows .dll> <macOS .dylib> [Variant ...]
"""
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
from package import VARIANTS, add, documentation  # noqa: E402

PLATFORMS = (("linux64", "so"), ("win64", "dll"), ("darwin64", "dylib"))


def main() -> None:
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    libraries = [Path(p) for p in sys.argv[1:4]]
    variants = sys.argv[4:] or VARIANTS
    for lib in libraries:
        if not lib.is_file():
            sys.exit(f"error: {lib} is missing; run scripts/release")
    blobs = [lib.read_bytes() for lib in libraries]
    out_dir = REPO / "dist" / "release"
    out_dir.mkdir(parents=True, exist_ok=True)
    for v in variants:
        xml = (REPO / "modelDescription" / f"{v}.xml").read_bytes()
        root = ET.fromstring(xml)
        identifier = root.find("CoSimulation").get("modelIdentifier")
        if identifier != v:
            sys.exit(f"error: {v}.xml: modelIdentifier {identifier!r}")
        fmu = out_dir / f"{v}.fmu"
        tmp = fmu.with_suffix(".fmu.tmp")
        with zipfile.ZipFile(tmp, "w") as zf:
            add(zf, "modelDescription.xml", xml)
            for (platform, ext), blob in zip(PLATFORMS, blobs):
                add(zf, f"binaries/{platform}/{identifier}.{ext}", blob, 0o755)
            add(zf, "documentation/index.html", documentation(root).encode("utf-8"))
        tmp.replace(fmu)
        print(f"{str(fmu.relative_to(REPO)):<44} {fmu.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main()
