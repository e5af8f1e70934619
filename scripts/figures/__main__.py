"""Redraw the figures from CSVs already written (no sweep is run):

    .venv/bin/python scripts/figures [--from out] [--docs docs/img] [--no-report] [--data-commit SHA]

writes out/wp_<scene>.png, out/stability_map.png and out/report.html from out/*.csv, and with
--docs copies the PNGs into that folder with commit.txt beside them. The scene descriptions come
from scripts/cosim (figures.from_cosim); where that cannot be imported, from the CSVs' names.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

SCRIPTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(SCRIPTS))

from figures.publish import publish  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--from", dest="src", default=str(SCRIPTS.parent / "out"), help="the folder of the CSVs")
    ap.add_argument("--docs", default=None, help="also copy the PNGs here (e.g. docs/img)")
    ap.add_argument("--no-report", action="store_true", help="do not write report.html")
    ap.add_argument("--data-commit", default=None, help="the commit the CSVs were made at (default: HEAD)")
    args = ap.parse_args(argv)
    try:
        from figures.from_cosim import descriptions
        desc = descriptions()
    except ImportError as e:
        print(f"  note: scene descriptions from the CSV names only ({e})", file=sys.stderr)
        desc = {}
    written = publish(args.src, docs=args.docs, report_page=not args.no_report, repo=SCRIPTS.parent,
                      data_commit=args.data_commit, **desc)
    for path, size in written.items():
        print(f"  wrote {path} ({size / 1000:.0f} kB)")


if __name__ == "__main__":
    main()
