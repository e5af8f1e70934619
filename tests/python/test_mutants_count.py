"""scripts/mutants_count.py, the counting behind ./scripts/mutants, on made-up outcomes: the
equivalent mutants are read from the 'Equivalent mutants' table only (escaped pipes undone),
survivors listed there count as equivalent, the others as survived, and a run that tested fewer
mutants than it listed is partial. Uses pytest and the standard library."""
from __future__ import annotations

import json

import conftest  # noqa: F401  (puts scripts/ on sys.path)
import mutants_count  # noqa: E402

TABLE = """# Doc
## Mutation testing
| area | mutants |
|---|---|
| `not/a/mutant.rs:1:1: replace x` | a results table, not the equivalents |
### Equivalent mutants
| mutant | why |
|---|---|
| `src/a.rs:3:5: replace && with \\|\\| in f` | unreachable |
| `src/a.rs:9:1: replace g -> bool with true` | always true |
## Next section
| `src/a.rs:12:1: replace h -> i32 with 0` | another table |
"""


def test_equivalent_names_come_from_their_table_only():
    assert mutants_count.equivalent_names(TABLE) == {
        "src/a.rs:3:5: replace && with || in f", "src/a.rs:9:1: replace g -> bool with true"}


def test_report_counts_equivalent_survived_and_partial(tmp_path, monkeypatch, capsys):
    mo = tmp_path / "mutants.out"
    mo.mkdir()
    names = [f"src/a.rs:{i}:1: m{i}" for i in range(6)] + ["src/a.rs:3:5: replace && with || in f"]
    (mo / "mutants.json").write_text(json.dumps([{"name": n} for n in names]))
    (mo / "caught.txt").write_text("src/a.rs:0:1: m0\nsrc/a.rs:1:1: m1\n")
    (mo / "missed.txt").write_text("src/a.rs:2:1: m2\nsrc/a.rs:3:5: replace && with || in f\n")
    (mo / "timeout.txt").write_text("src/a.rs:4:1: m4\n")
    (mo / "unviable.txt").write_text("")
    parse = mutants_count.equivalent_names
    monkeypatch.setattr(mutants_count, "equivalent_names", lambda: parse(TABLE))
    c = mutants_count.report("src/a.rs", str(tmp_path), "2", "rust")
    assert c == {"mutants": 7, "tested": 5, "caught": 2, "survived": 1, "equivalent": 1, "timeout": 1,
                 "unviable": 0}
    out = capsys.readouterr().out
    assert "PARTIAL" in out and "survived: src/a.rs:2:1: m2" in out
    assert "caught 75.0 %" in out          # (2 caught + 1 timeout) of 4 non-equivalent
    saved = json.loads((tmp_path / "counts.json").read_text())
    assert saved["partial"] is True and saved["survivors"] == ["src/a.rs:2:1: m2"]
