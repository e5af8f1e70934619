#!/usr/bin/env python3
"""Make the minimal macOS link SDK for the release build: <out>/usr/lib/libSystem.tbd (+ libc.tbd,
libm.tbd, libiconv.tbd as symlinks to it), derived from the libSystem.tbd in the pinned `ziglang` wheel.

Two edits make it usable by ld64.lld for both macOS architectures:
- the `arm64e.x1-*` targets are dropped (ld64.lld does not know that architecture);
- `arm64-*` is listed beside every `arm64e-*` target (the wheel lists arm64e only; arm64 slices
  link against the same symbols, and an arm64 dylib resolves them from the system's libSystem).
Usage: macos_sdk.py <out dir>
"""
import re
import sys
from pathlib import Path

import ziglang

TBD = Path(ziglang.__file__).parent / "lib" / "libc" / "darwin" / "libSystem.tbd"


def fix_targets(match: re.Match) -> str:
    items = [s.strip() for s in match.group(1).split(",") if s.strip()]
    kept = [s for s in items if not s.startswith("arm64e.x1-")]
    out = []
    for s in kept:
        if s.startswith("arm64e-"):
            arm64 = "arm64-" + s[len("arm64e-"):]
            if arm64 not in kept and arm64 not in out:
                out.append(arm64)
        out.append(s)
    if not out:
        sys.exit(f"error: a targets list of {TBD} holds only arm64e.x1 targets; update macos_sdk.py")
    return "[ " + ", ".join(out) + " ]"


def main() -> None:
    out = Path(sys.argv[1])
    text = TBD.read_text()
    fixed, n = re.subn(r"\[([^\[\]]*?-mac(?:os|catalyst)[^\[\]]*)\]", fix_targets, text, flags=re.S)
    if n == 0 or "arm64e.x1" in fixed:
        sys.exit(f"error: unexpected layout of {TBD}")
    lib = out / "usr" / "lib"
    lib.mkdir(parents=True, exist_ok=True)
    target = lib / "libSystem.tbd"
    if not target.is_file() or target.read_text() != fixed:
        target.write_text(fixed)
    # the libc crate names iconv for Apple targets; nothing here uses it, so the alias only
    # satisfies -liconv (a use would fail to link: libSystem does not export iconv)
    for alias in ("libc.tbd", "libm.tbd", "libiconv.tbd"):
        link = lib / alias
        if not link.is_symlink():
            link.unlink(missing_ok=True)
            link.symlink_to("libSystem.tbd")
    print(f"macOS link SDK: {out} ({n} target lists rewritten from {TBD})")


if __name__ == "__main__":
    main()
