"""The counts of one ./scripts/mutants area: mutants, caught, survived, equivalent, timeout,
unviable, from cargo-mutants' mutants.out/ (caught.txt, missed.txt, timeout.txt, unviable.txt,
mutants.json) or mutmut's `results --all true` listing; the mutants docs/hardening.md lists as
equivalent (backticked names in the first column of its "Equivalent mutants" table) are
counted as equivalent, not as survived. Each survivor is printed by name. Standard library only.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
HARDENING = REPO / "docs" / "hardening.md"


def equivalent_names(text: str | None = None) -> set[str]:
    """The mutant names of the 'Equivalent mutants' table of docs/hardening.md."""
    text = HARDENING.read_text(encoding="utf-8") if text is None else text
    names, inside = set(), False
    for line in text.splitlines():
        if line.startswith("#"):
            inside = "equivalent mutants" in line.lower()
            continue
        m = re.match(r"\|\s*`([^`]+)`\s*\|", line)
        if inside and m:
            names.add(m.group(1).replace("\\|", "|").strip())   # a table cell escapes its pipes
    return names


def _lines(p: Path) -> list[str]:
    return [x.strip() for x in p.read_text().splitlines() if x.strip()] if p.is_file() else []


def rust_outcomes(out: Path) -> dict[str, list[str]]:
    mo = out / "mutants.out"
    total = []
    if (mo / "mutants.json").is_file():
        for m in json.loads((mo / "mutants.json").read_text()):
            total.append(m.get("name") or f"{m['file']}:{m['span']['start']['line']}: {m.get('description', '')}")
    return {"mutants": total, "caught": _lines(mo / "caught.txt"), "missed": _lines(mo / "missed.txt"),
            "timeout": _lines(mo / "timeout.txt"), "unviable": _lines(mo / "unviable.txt")}


def python_outcomes(out: Path) -> dict[str, list[str]]:
    res = {"mutants": [], "caught": [], "missed": [], "timeout": [], "unviable": [], "not run": []}
    kind = {"killed": "caught", "survived": "missed", "timeout": "timeout", "suspicious": "timeout",
            "segfault": "caught", "no tests": "missed", "skipped": "unviable",
            "not checked": "not run"}
    for line in _lines(out / "results.txt"):
        m = re.match(r"(\S+):\s*(.+)$", line)
        if not m or m.group(2) not in kind:
            continue
        res["mutants"].append(m.group(1))
        res[kind[m.group(2)]].append(m.group(1))
    return res


def report(path: str, out: str, rc: str, kind: str) -> dict:
    o = rust_outcomes(Path(out)) if kind == "rust" else python_outcomes(Path(out))
    eq = equivalent_names()
    equivalent = [m for m in o["missed"] if m in eq]
    survived = [m for m in o["missed"] if m not in eq]
    tested = len(o["caught"]) + len(o["missed"]) + len(o["timeout"]) + len(o["unviable"])
    total = len(o["mutants"]) or tested
    partial = tested < total or rc not in ("0", "2")   # cargo-mutants: 2 = some survived
    counts = {"mutants": total, "tested": tested, "caught": len(o["caught"]), "survived": len(survived),
              "equivalent": len(equivalent), "timeout": len(o["timeout"]), "unviable": len(o["unviable"])}
    nonequiv = counts["caught"] + counts["survived"] + counts["timeout"]
    score = 100.0 * (counts["caught"] + counts["timeout"]) / nonequiv if nonequiv else float("nan")
    print(f"    {path}: " + ", ".join(f"{k} {v}" for k, v in counts.items())
          + f"; caught {score:.1f} % of the non-equivalent tested"
          + (" (PARTIAL: the budget ran out or the run stopped)" if partial else ""))
    for m in survived:
        print(f"      survived: {m}")
    (Path(out) / "counts.json").write_text(json.dumps({**counts, "partial": partial, "survivors": survived}))
    return counts
