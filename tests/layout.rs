//! The house rules a reader relies on, checked on the source tree itself:
//! - no import cycle between the files of `src/` (and of `master/src/`, the master's crate): each file's dependencies (its `use`
//!   declarations and the `crate::`, `super::`, `self::` paths in its code, resolved to the file
//!   that defines the item, through `pub use` re-exports) form a graph without cycles, so every
//!   file reads on top of the ones it uses and none of those uses it back;
//! - no source file (`.rs`, `.py` under src/, tests/, benches/, fuzz/, scripts/, bodies/,
//!   master/, fmi_shared/, empty_fmu/) above
//!   1,000 lines, except the literal variable table (src/model/variables.rs).
//!
//! Plain std: a small scanner for Rust paths (comments and literals stripped), no parser crate.
//! The checks are also run against made-up trees, so that a cycle or a long file is seen.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 1000;
/// The folders whose `.rs` and `.py` files the length rule covers: every folder of code the
/// docs/README.md layout names.
const CODE_DIRS: &[&str] = &[
    "src",
    "tests",
    "benches",
    "fuzz",
    "scripts",
    "bodies",
    "master",
    "fmi_shared",
    "empty_fmu",
];
/// Files allowed above `MAX_LINES`: the literal variable table, one row per variable.
const LONG_ALLOWED: &[&str] = &["src/model/variables.rs"];

/// A source file of the crate: its module path from the crate root and its text (comments and
/// literals blanked).
struct Source {
    module: Vec<String>,
    code: String,
}

/// Comments, string and char literals replaced by spaces (newlines kept).
fn strip(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied().unwrap_or('\0');
        if c == '/' && next == '/' {
            while i < b.len() && b[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == '/' && next == '*' {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
        } else if c == 'r' && (next == '"' || next == '#') && !ident_char(prev(&b, i)) {
            // raw string r"..." / r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            for &ch in &b[i..j.min(b.len())] {
                out.push(blank(ch));
            }
            i = j;
        } else if c == '"' {
            out.push(' ');
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    out.push(' ');
                    i += 1;
                }
                if i < b.len() {
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
            out.push(' ');
            i += 1;
        } else if c == '\'' {
            // a char literal ('x', '\n', '\u{..}'), not a lifetime ('a)
            let close = if next == '\\' {
                (i + 2..b.len().min(i + 12)).find(|&j| b[j] == '\'')
            } else if b.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match close {
                Some(j) => {
                    for _ in i..=j {
                        out.push(' ');
                    }
                    i = j + 1;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn prev(b: &[char], i: usize) -> char {
    if i == 0 {
        ' '
    } else {
        b[i - 1]
    }
}

fn ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Paths of a `use` tree (`a::{b, c::{d as e, self}, *}`), each as its segments; `self` ends a
/// path at its prefix, an alias is dropped, a glob stands for its prefix.
fn expand_use(tree: &str) -> Vec<Vec<String>> {
    fn go(prefix: &[String], s: &str, out: &mut Vec<Vec<String>>) {
        let s = s.trim();
        if s.is_empty() {
            return;
        }
        if let Some(open) = s.find('{') {
            let head: Vec<String> = segments(&s[..open]);
            let inner = &s[open + 1..s.rfind('}').unwrap_or(s.len())];
            let mut base = prefix.to_vec();
            base.extend(head);
            for part in split_top(inner) {
                go(&base, part, out);
            }
            return;
        }
        let s = s.split(" as ").next().unwrap_or(s);
        let mut path = prefix.to_vec();
        for seg in segments(s) {
            if seg == "self" && !path.is_empty() {
                continue;
            }
            if seg != "*" {
                path.push(seg);
            }
        }
        out.push(path);
    }
    let mut out = Vec::new();
    go(&[], tree, &mut out);
    out
}

fn segments(s: &str) -> Vec<String> {
    s.split("::")
        .map(|x| x.trim().to_string())
        .filter(|x| !x.is_empty())
        .collect()
}

/// Split at the commas that are not inside braces.
fn split_top(s: &str) -> Vec<&str> {
    let (mut depth, mut start, mut parts) = (0, 0, Vec::new());
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&s[start..]);
    parts
}

/// Every path the code names, with the inline modules (`mod tests { .. }`) it sits in: `use`
/// trees and the `crate::`/`super::`/`self::`/`connector_fmu::` paths and `child::` paths of the
/// code.
fn paths_in(code: &str, children: &BTreeSet<String>) -> Vec<(Vec<String>, Vec<String>)> {
    let b: Vec<char> = code.chars().collect();
    // inline module blocks: (name, open index, close index)
    let mut blocks: Vec<(String, usize, usize)> = Vec::new();
    let mut stack: Vec<(Option<String>, usize)> = Vec::new();
    let mut pending: Option<String> = None;
    let mut i = 0;
    while i < b.len() {
        if starts_word(&b, i, "mod") {
            let name: String = b[i + 3..]
                .iter()
                .skip_while(|c| c.is_whitespace())
                .take_while(|c| ident_char(**c))
                .collect();
            let after =
                i + 3 + b[i + 3..].iter().take_while(|c| c.is_whitespace()).count() + name.len();
            let rest = b[after..].iter().find(|c| !c.is_whitespace());
            if rest == Some(&'{') {
                pending = Some(name);
            }
        }
        match b[i] {
            '{' => stack.push((pending.take(), i)),
            '}' => {
                if let Some((Some(name), open)) = stack.pop() {
                    blocks.push((name, open, i));
                }
            }
            _ => {}
        }
        i += 1;
    }
    let inline_at = |pos: usize| -> Vec<String> {
        let mut v: Vec<&(String, usize, usize)> = blocks
            .iter()
            .filter(|(_, o, c)| *o < pos && pos < *c)
            .collect();
        v.sort_by_key(|(_, o, _)| *o);
        v.into_iter().map(|(n, _, _)| n.clone()).collect()
    };
    let mut out = Vec::new();
    // use declarations (also those a macro body writes, `use $crate::..`)
    let mut uses = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if starts_word(&b, i, "use") {
            let end = (i..b.len()).find(|&j| b[j] == ';').unwrap_or(b.len());
            let tree: String = b[i + 3..end].iter().collect();
            for p in expand_use(&tree.replace("$crate", "crate")) {
                out.push((inline_at(i), p));
            }
            uses.push(i..end);
            i = end;
        }
        i += 1;
    }
    // paths in the code outside the use declarations
    let mut i = 0;
    while i < b.len() {
        if let Some(u) = uses.iter().find(|u| u.contains(&i)) {
            i = u.end;
            continue;
        }
        if ident_char(b[i]) && !ident_char(prev(&b, i)) && prev(&b, i) != ':' {
            let start = i;
            let mut j = i;
            let mut segs = Vec::new();
            loop {
                let s: String = b[j..].iter().take_while(|c| ident_char(**c)).collect();
                if s.is_empty() {
                    break;
                }
                j += s.chars().count();
                segs.push(s);
                if b.get(j) == Some(&':') && b.get(j + 1) == Some(&':') {
                    j += 2;
                } else {
                    break;
                }
            }
            let first = segs[0].as_str();
            let rooted = matches!(first, "crate" | "super" | "self" | "connector_fmu");
            if segs.len() > 1 && (rooted || children.contains(first)) {
                out.push((inline_at(start), segs));
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    out
}

fn starts_word(b: &[char], i: usize, w: &str) -> bool {
    let n = w.chars().count();
    !ident_char(prev(b, i))
        && b.len() >= i + n
        && b[i..i + n].iter().copied().eq(w.chars())
        && !b.get(i + n).copied().map(ident_char).unwrap_or(false)
}

/// The crate's files under `src/` (a binary under src/bin/ is its own crate: its module path
/// starts with `bin`, and it reaches the library through `connector_fmu::`).
fn sources(root: &Path) -> BTreeMap<PathBuf, Source> {
    let mut files = Vec::new();
    collect(&root.join("src"), &mut files);
    let mut out = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(root.join("src")).unwrap_or(&f).to_path_buf();
        let mut module: Vec<String> = rel
            .with_extension("")
            .iter()
            .map(|s| s.to_string_lossy().into_owned())
            .collect();
        // a directory module (mod.rs, lib.rs) is the module of its folder
        if module.last().is_some_and(|m| m == "mod" || m == "lib") {
            module.pop();
        }
        let text = std::fs::read_to_string(&f).unwrap_or_default();
        out.insert(
            rel,
            Source {
                module,
                code: strip(&text),
            },
        );
    }
    out
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The file-level import graph: file → the files whose items it names.
fn graph(files: &BTreeMap<PathBuf, Source>) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let by_module: BTreeMap<Vec<String>, PathBuf> = files
        .iter()
        .map(|(p, s)| (s.module.clone(), p.clone()))
        .collect();
    // re-exports: (file, name) → the path it re-exports
    let mut reexports: BTreeMap<(PathBuf, String), Vec<String>> = BTreeMap::new();
    for (p, s) in files {
        let mut i = 0;
        while let Some(k) = s.code[i..].find("pub use ") {
            let start = i + k + "pub use ".len();
            let end = s.code[start..]
                .find(';')
                .map_or(s.code.len(), |e| start + e);
            for path in expand_use(&s.code[start..end]) {
                if let Some(name) = path.last() {
                    reexports.insert((p.clone(), name.clone()), path.clone());
                }
            }
            i = end;
        }
    }
    let mut edges: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
    for (p, s) in files {
        let own = &s.module;
        let children: BTreeSet<String> = by_module
            .keys()
            .filter(|m| m.len() == own.len() + 1 && m.starts_with(own))
            .filter_map(|m| m.last().cloned())
            .collect();
        let bin = own.first().is_some_and(|m| m == "bin");
        let set = edges.entry(p.clone()).or_default();
        for (inline, path) in paths_in(&s.code, &children) {
            let here: Vec<String> = own.iter().chain(inline.iter()).cloned().collect();
            let Some(abs) = absolute(&here, &path, &children, bin) else {
                continue;
            };
            if let Some(target) = resolve(&abs, &by_module, files, &reexports, 0) {
                if &target != p {
                    set.insert(target);
                }
            }
        }
    }
    edges
}

/// `path` as seen from module `here`, from the crate root; None for a path outside the crate.
fn absolute(
    here: &[String],
    path: &[String],
    children: &BTreeSet<String>,
    bin: bool,
) -> Option<Vec<String>> {
    let first = path.first()?.as_str();
    let mut abs: Vec<String> = match first {
        "crate" if bin => return None,
        "crate" => Vec::new(),
        "connector_fmu" => Vec::new(),
        "self" => here.to_vec(),
        "super" => {
            let mut m = here.to_vec();
            let mut rest = path;
            while rest.first().is_some_and(|s| s == "super") {
                m.pop()?;
                rest = &rest[1..];
            }
            m.extend(rest.iter().cloned());
            return Some(m);
        }
        c if children.contains(c) => {
            let mut m = here.to_vec();
            m.push(c.to_string());
            m.extend(path[1..].iter().cloned());
            return Some(m);
        }
        _ => return None,
    };
    abs.extend(path[1..].iter().cloned());
    Some(abs)
}

/// The file defining the item at `abs` (following `pub use` re-exports of directory modules).
fn resolve(
    abs: &[String],
    by_module: &BTreeMap<Vec<String>, PathBuf>,
    files: &BTreeMap<PathBuf, Source>,
    reexports: &BTreeMap<(PathBuf, String), Vec<String>>,
    depth: usize,
) -> Option<PathBuf> {
    let mut k = 0;
    while k < abs.len() && by_module.contains_key(&abs[..k + 1]) {
        k += 1;
    }
    let file = by_module.get(&abs[..k])?.clone();
    if let (Some(item), true) = (abs.get(k), depth < 8) {
        if let Some(target) = reexports.get(&(file.clone(), item.clone())) {
            let from = &files[&file];
            let here = from.module.clone();
            let kids: BTreeSet<String> = by_module
                .keys()
                .filter(|m| m.len() == here.len() + 1 && m.starts_with(&here))
                .filter_map(|m| m.last().cloned())
                .collect();
            if let Some(t) = absolute(&here, target, &kids, false) {
                let mut t = t;
                t.extend(abs[k + 1..].iter().cloned());
                return resolve(&t, by_module, files, reexports, depth + 1);
            }
        }
    }
    Some(file)
}

/// The cycles of a graph: each strongly connected component of two or more files, as a
/// closed path through it.
fn cycles(edges: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    let mut found = Vec::new();
    let mut reported: BTreeSet<PathBuf> = BTreeSet::new();
    for start in edges.keys() {
        if reported.contains(start) {
            continue;
        }
        // a shortest path back to `start` (breadth first)
        let mut prev: BTreeMap<PathBuf, PathBuf> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start.clone()]);
        let mut closing = None;
        while let Some(n) = queue.pop_front() {
            for m in edges.get(&n).into_iter().flatten() {
                if m == start {
                    closing = Some(n.clone());
                    break;
                }
                if !prev.contains_key(m) {
                    prev.insert(m.clone(), n.clone());
                    queue.push_back(m.clone());
                }
            }
            if closing.is_some() {
                break;
            }
        }
        if let Some(mut n) = closing {
            let mut path = vec![start.clone()];
            let mut back = vec![n.clone()];
            while let Some(p) = prev.get(&n) {
                if p == start {
                    break;
                }
                back.push(p.clone());
                n = p.clone();
            }
            back.reverse();
            path.extend(back);
            path.push(start.clone());
            reported.extend(path.iter().cloned());
            found.push(path);
        }
    }
    found
}

fn show(cycle: &[PathBuf]) -> String {
    cycle
        .iter()
        .map(|p| format!("src/{}", p.display()))
        .collect::<Vec<_>>()
        .join(" -> ")
}

#[test]
fn no_import_cycle_between_files_of_src() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = sources(root);
    assert!(
        files.len() > 30,
        "the scan found {} files under src/",
        files.len()
    );
    let edges = graph(&files);
    // the scan sees the layering: the boundary uses the instance, the instance the model,
    // the model the physics (a scan that resolves nothing would pass the cycle check vacuously)
    let has = |from: &str, to: &str| edges[Path::new(from)].contains(Path::new(to));
    assert!(has("model/access.rs", "model/variables.rs"));
    assert!(has("model/access.rs", "physics/connector.rs"));
    assert!(has("instance/mod.rs", "model/access.rs"));
    let found = cycles(&edges);
    assert!(
        found.is_empty(),
        "import cycles between files (each file must use only files that do not use it back):\n{}",
        found.iter().map(|c| show(c)).collect::<Vec<_>>().join("\n")
    );
}

#[test]
fn no_import_cycle_between_files_of_the_masters_src() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("master");
    let files = sources(&root);
    assert!(
        files.len() > 15,
        "the scan found {} files under master/src/",
        files.len()
    );
    let edges = graph(&files);
    // the scan sees the master's layering (the time loop on the exchange, the slave on the
    // FMI boundary)
    let has = |from: &str, to: &str| edges[Path::new(from)].contains(Path::new(to));
    assert!(has("execution.rs", "exchange.rs"));
    assert!(has("slave.rs", "ffi/fmi2.rs"));
    assert!(has("structure.rs", "ssp/mod.rs"));
    let found = cycles(&edges);
    assert!(
        found.is_empty(),
        "import cycles between files of master/src:\n{}",
        found.iter().map(|c| show(c)).collect::<Vec<_>>().join("\n")
    );
}

#[test]
fn the_cycle_check_sees_a_cycle() {
    let file = |module: &[&str], code: &str| Source {
        module: module.iter().map(|s| s.to_string()).collect(),
        code: strip(code),
    };
    let a = "use super::b::{X, Y as Z};\n// use super::c;\npub struct A;";
    let b_uses_a = "pub struct X; fn f() -> crate::m::a::A { todo!() }";
    let mut files = BTreeMap::new();
    files.insert(PathBuf::from("lib.rs"), file(&[], "pub mod m;"));
    files.insert(
        PathBuf::from("m/mod.rs"),
        file(&["m"], "pub mod a; pub mod b;"),
    );
    files.insert(PathBuf::from("m/a.rs"), file(&["m", "a"], a));
    files.insert(PathBuf::from("m/b.rs"), file(&["m", "b"], b_uses_a));
    let edges = graph(&files);
    assert!(edges[Path::new("m/a.rs")].contains(Path::new("m/b.rs")));
    assert!(edges[Path::new("m/b.rs")].contains(Path::new("m/a.rs")));
    assert_eq!(cycles(&edges).len(), 1, "{:?}", cycles(&edges));
    // with b no longer naming a there is none: comments and strings are not code
    let b_names_a_in_text = "pub struct X; /* crate::m::a::A */ const S: &str = \"crate::m::a\";";
    files.insert(
        PathBuf::from("m/b.rs"),
        file(&["m", "b"], b_names_a_in_text),
    );
    assert!(cycles(&graph(&files)).is_empty());
}

/// Source files (.rs, .py) under the project's code folders, as paths relative to `root`.
fn code_files(root: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.filter_map(|e| e.ok()) {
            let p = e.path();
            let name = e.file_name().to_string_lossy().into_owned();
            if p.is_dir() {
                if !matches!(
                    name.as_str(),
                    "target" | "corpus" | "artifacts" | "__pycache__"
                ) && !name.starts_with('.')
                {
                    walk(root, &p, out);
                }
            } else if name.ends_with(".rs") || name.ends_with(".py") {
                out.push(p.strip_prefix(root).unwrap_or(&p).to_path_buf());
            }
        }
    }
    let mut out = Vec::new();
    for d in CODE_DIRS {
        walk(root, &root.join(d), &mut out);
    }
    out.sort();
    out
}

fn long_files(root: &Path) -> Vec<(PathBuf, usize)> {
    code_files(root)
        .into_iter()
        .filter_map(|p| {
            let n = std::fs::read_to_string(root.join(&p)).ok()?.lines().count();
            let allowed = LONG_ALLOWED.iter().any(|a| Path::new(a) == p);
            (n > MAX_LINES && !allowed).then_some((p, n))
        })
        .collect()
}

#[test]
fn no_source_file_above_a_thousand_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    assert!(code_files(root).len() > 50);
    let long = long_files(root);
    assert!(
        long.is_empty(),
        "files above {MAX_LINES} lines (split them into parts that name what they hold): {long:?}"
    );
}

#[test]
fn the_length_check_sees_a_long_file() {
    let dir = std::env::temp_dir().join(format!("layout-test-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("scripts")).unwrap();
    std::fs::write(dir.join("scripts/long.py"), "x = 1\n".repeat(MAX_LINES + 1)).unwrap();
    std::fs::write(dir.join("scripts/short.py"), "x = 1\n".repeat(MAX_LINES)).unwrap();
    let long = long_files(&dir);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(
        long,
        vec![(PathBuf::from("scripts/long.py"), MAX_LINES + 1)]
    );
}

/// A long file in any code folder is seen, the shared rlib's included (one file per folder of
/// `CODE_DIRS`, one line too many each).
#[test]
fn the_length_check_covers_every_code_folder() {
    let dir = std::env::temp_dir().join(format!("layout-dirs-{}", std::process::id()));
    let mut want = Vec::new();
    for d in CODE_DIRS {
        std::fs::create_dir_all(dir.join(d).join("inner")).unwrap();
        let p = PathBuf::from(d).join("inner").join("long.rs");
        std::fs::write(dir.join(&p), "//\n".repeat(MAX_LINES + 1)).unwrap();
        want.push((p, MAX_LINES + 1));
    }
    let mut long = long_files(&dir);
    std::fs::remove_dir_all(&dir).ok();
    long.sort();
    want.sort();
    assert_eq!(long, want);
}

/// Every top-level folder of the repository that holds Rust or Python code is one the length
/// rule covers (fmi_shared/ and empty_fmu/ among them); build output and environments aside.
#[test]
fn every_code_folder_is_covered() {
    fn has_code(p: &Path) -> bool {
        std::fs::read_dir(p)
            .into_iter()
            .flatten()
            .flatten()
            .any(|e| {
                let (p, name) = (e.path(), e.file_name().to_string_lossy().into_owned());
                if p.is_dir() {
                    name != "target" && !name.starts_with('.') && has_code(&p)
                } else {
                    name.ends_with(".rs") || name.ends_with(".py")
                }
            })
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut uncovered = Vec::new();
    for e in std::fs::read_dir(root).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let built = matches!(name.as_str(), "target" | "dist" | "out") || name.starts_with('.');
        if e.path().is_dir() && !built && has_code(&e.path()) && !CODE_DIRS.contains(&name.as_str())
        {
            uncovered.push(name);
        }
    }
    assert!(
        uncovered.is_empty(),
        "code folders outside the length rule: {uncovered:?}"
    );
}

/// The README stays a front page: the quick start, the variants and where to read on; measured
/// tables live in docs/.
#[test]
fn the_readme_stays_short() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let n = std::fs::read_to_string(root.join("README.md")).map_or(0, |t| t.lines().count());
    assert!(n > 50 && n <= 300, "README.md has {n} lines (at most 300)");
}
