#!/usr/bin/env python3
"""Package the release FMUs of one crate's models: dist/release/<Model>.fmu (FMI 2.0) with
binaries for linux64 (glibc 2.17), win64 and darwin64 (universal x86_64 + arm64), and
dist/release/fmi3/<Model>.fmu (FMI 3.0) with x86_64-linux, x86_64-windows, x86_64-darwin and
aarch64-darwin (the macOS slices the universal binary is made of), all from the one library per
platform that scripts/release built for the crate (already stripped at link time; it exports both
the fmi2* and the fmi3* functions). The model descriptions carry the commit time as
generationDateAndTime, as in dist/.

Usage: release_package.py <crate> <linux .so> <windows .dll> <macOS universal .dylib>
                          <macOS x86_64 .dylib> <macOS arm64 .dylib> [Model ...]
       (crate: connector_fmu or body_fmu; default: every model of the crate)
"""
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
from package import CRATES, generation_date, package  # noqa: E402
from package_fmi3 import documentation as documentation_fmi3  # noqa: E402

# (directory, extension, index of the library on the command line)
FMI2_PLATFORMS = (("linux64", "so", 0), ("win64", "dll", 1), ("darwin64", "dylib", 2))
FMI3_PLATFORMS = (("x86_64-linux", "so", 0), ("x86_64-windows", "dll", 1),
                  ("x86_64-darwin", "dylib", 3), ("aarch64-darwin", "dylib", 4))


def main() -> None:
    if len(sys.argv) < 7:
        sys.exit(__doc__)
    crate = next((c for c in CRATES if c.name == sys.argv[1]), None)
    if crate is None:
        sys.exit(f"error: unknown crate {sys.argv[1]!r}; known: {', '.join(c.name for c in CRATES)}")
    libraries = [Path(p) for p in sys.argv[2:7]]
    models = sys.argv[7:] or list(crate.models)
    unknown = sorted(set(models) - set(crate.models))
    if unknown:
        sys.exit(f"error: {crate.name} has no model(s) {', '.join(unknown)}")
    for lib in libraries:
        if not lib.is_file():
            sys.exit(f"error: {lib} is missing; run scripts/release")
    blobs = [lib.read_bytes() for lib in libraries]
    out_dir = REPO / "dist" / "release"
    (out_dir / "fmi3").mkdir(parents=True, exist_ok=True)
    date = generation_date()
    for m in models:
        for fmu in (package(m, out_dir, [(p, ext, blobs[i]) for p, ext, i in FMI2_PLATFORMS], date),
                    package(m, out_dir / "fmi3", [(p, ext, blobs[i]) for p, ext, i in FMI3_PLATFORMS], date,
                            fmi3=True, doc=documentation_fmi3)):
            print(f"{str(fmu.relative_to(REPO)):<44} {fmu.stat().st_size:>12,d} bytes")


if __name__ == "__main__":
    main()
