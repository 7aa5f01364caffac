//! Tidy: the dependency table of ARCHITECTURE.md ("## Dependencies") is the
//! law of `src/`. Every `crate::<module>` path in a module's files (imports
//! and inline paths alike, comments excluded) must be allowed by the table.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A table of ARCHITECTURE.md under `heading` whose header row starts with
/// `| {first}`: first column → the names of the second (backticks removed).
fn table(heading: &str, first: &str) -> BTreeMap<String, BTreeSet<String>> {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let section = text.split(heading).nth(1).unwrap_or_else(|| panic!("a '{heading}' section"));
    let mut table = BTreeMap::new();
    for line in section.lines().skip_while(|l| !l.starts_with(&format!("| {first}"))).skip(2) {
        if !line.starts_with('|') {
            break;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let name = |s: &str| s.trim().trim_matches('`').to_string();
        let uses: BTreeSet<String> =
            cells.get(1).map_or("", |c| c).split(',').map(name).filter(|s| !s.is_empty()).collect();
        table.insert(name(cells[0]), uses);
    }
    table
}

/// module → modules it may use, parsed from the "## Dependencies" table.
fn allowed() -> BTreeMap<String, BTreeSet<String>> {
    table("## Dependencies", "module")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("readable src") {
        let p = e.expect("entry").path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The top module a file of `src/` belongs to (`None` for lib.rs and main.rs).
fn module_of(file: &Path) -> Option<String> {
    let rel = file.strip_prefix(root().join("src")).ok()?;
    let first = rel.components().next()?.as_os_str().to_string_lossy().into_owned();
    let m = first.trim_end_matches(".rs").to_string();
    (m != "lib" && m != "main").then_some(m)
}

/// Every `crate::<name>` on non-comment lines, with its line number.
fn crate_paths(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(k) = rest.find("crate::") {
            let tail = &rest[k + "crate::".len()..];
            let name: String = tail.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            if !name.is_empty() {
                out.push((i + 1, name));
            }
            rest = tail;
        }
        // `use crate::{a, b}` names several modules at once
        if let Some(k) = code.find("crate::{") {
            let inner = code[k + "crate::{".len()..].split('}').next().unwrap_or("");
            for part in inner.split(',') {
                let name: String = part.trim().chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
                if !name.is_empty() {
                    out.push((i + 1, name));
                }
            }
        }
    }
    out
}

#[test]
fn every_module_uses_only_what_architecture_md_allows() {
    let table = allowed();
    assert!(table.contains_key("beam") && table.contains_key("cli"), "table not parsed: {table:?}");
    let mut files = Vec::new();
    rust_files(&root().join("src"), &mut files);
    files.sort();
    let mut violations = Vec::new();
    for f in &files {
        let Some(module) = module_of(f) else { continue };
        let Some(ok) = table.get(&module) else {
            violations.push(format!("{}: module `{module}` is not in ARCHITECTURE.md's table", f.display()));
            continue;
        };
        let text = std::fs::read_to_string(f).expect("readable");
        for (line, used) in crate_paths(&text) {
            if used != module && !ok.contains(&used) {
                violations.push(format!("{}:{line}: `{module}` uses `crate::{used}`", f.display()));
            }
        }
    }
    assert!(violations.is_empty(), "imports the table does not allow:\n{}", violations.join("\n"));
}

#[test]
fn the_scanner_sees_imports_inline_paths_and_groups() {
    let found =
        crate_paths("use crate::beam::X;\nlet y = crate::cli::run();\n// crate::report\nuse crate::{bayes, error::E};");
    let names: Vec<&str> = found.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(names, ["beam", "cli", "bayes", "error"]);
}

/// The text of `line` before a `//` comment.
fn code_of(line: &str) -> &str {
    line.split("//").next().unwrap_or("")
}

/// The code of a file up to its unit tests (`#[cfg(test)]`), comments removed.
fn code_before_tests(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        out.push_str(code_of(line));
        out.push('\n');
    }
    out
}

/// The first path segment after every occurrence of `prefix` in `code`
/// (`prefix{a, b::c}` yields `a` and `b`).
fn names_after(code: &str, prefix: &str) -> BTreeSet<String> {
    let ident =
        |s: &str| -> String { s.trim().chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect() };
    let mut out = BTreeSet::new();
    let mut rest = code;
    while let Some(k) = rest.find(prefix) {
        let before = rest[..k].chars().last();
        rest = &rest[k + prefix.len()..];
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        if let Some(inner) = rest.strip_prefix('{') {
            // a group: its top-level names
            let mut depth = 0;
            let mut item = String::new();
            for c in inner.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.insert(ident(&item));
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                if depth == 0 {
                    item.push(c);
                }
            }
            out.insert(ident(&item));
        } else {
            out.insert(ident(rest));
        }
    }
    out.remove("");
    out
}

/// The files of one module directory that `file` uses: `super::f` or
/// `crate::<module>::f` for a sibling file `f`, and `mod.rs` for any other
/// name reached through `super::` (an item defined or re-exported there).
/// `mod.rs` is the module's facade: its `mod` and `pub use` lines are not
/// uses; its own code's paths to a sibling (`f::…`) are.
fn sibling_uses(module: &str, file: &str, text: &str, siblings: &BTreeSet<String>) -> BTreeSet<String> {
    let code = code_before_tests(text);
    let mut used = BTreeSet::new();
    if file == "mod" {
        let own: String = code
            .lines()
            .filter(|l| {
                let t = l.trim_start();
                !(t.starts_with("pub use") || t.starts_with("pub(crate) use") || t.contains("mod "))
            })
            .collect::<Vec<_>>()
            .join("\n");
        for s in siblings {
            if names_after(&own, &format!("{s}::")).is_empty() && !own.contains(&format!("{s}::")) {
                continue;
            }
            used.insert(s.clone());
        }
    } else {
        for n in names_after(&code, "super::") {
            used.insert(if siblings.contains(&n) { n } else { "mod".to_string() });
        }
    }
    for n in names_after(&code, &format!("crate::{module}::")) {
        if siblings.contains(&n) {
            used.insert(n);
        }
    }
    used.remove(file);
    used
}

/// A cycle in `graph` (file → files it uses), if any, as the files along it.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for m in graph.get(n).into_iter().flatten() {
            match state.get(m).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|s| s == m).expect("on the stack");
                    let mut cycle = stack[start..].to_vec();
                    cycle.push(m.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(m, graph, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in graph.keys() {
        if state.get(n).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, graph, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

/// The `.rs` files under `dir` at any depth.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    rust_files(dir, &mut out);
    out.sort();
    out
}

/// No circle between the files of a module, nor between the rooms
/// (sub-folders) of one: in every folder of `src/<module>/…`, each file's
/// uses of its siblings (`super::…`, `crate::<path>::…`) and each sub-folder's
/// uses of its siblings (by any file inside it) form a graph without cycles,
/// so every file and room can be read after those it builds on.
#[test]
fn no_circle_between_the_files_of_a_module() {
    fn folders(dir: &Path, path: &str, out: &mut Vec<(PathBuf, String)>) {
        out.push((dir.to_path_buf(), path.to_string()));
        let mut subs: Vec<PathBuf> = std::fs::read_dir(dir)
            .expect("readable")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.is_dir())
            .collect();
        subs.sort();
        for sub in subs {
            let name = sub.file_name().expect("name").to_string_lossy().into_owned();
            folders(&sub, &format!("{path}::{name}"), out);
        }
    }
    let mut all = Vec::new();
    for e in std::fs::read_dir(root().join("src")).expect("readable src") {
        let dir = e.expect("entry").path();
        if dir.is_dir() {
            let module = dir.file_name().expect("name").to_string_lossy().into_owned();
            folders(&dir, &module, &mut all);
        }
    }
    all.sort();
    let mut circles = Vec::new();
    for (dir, path) in &all {
        let mut texts = BTreeMap::new();
        let mut rooms = BTreeMap::new();
        for f in std::fs::read_dir(dir).expect("readable module") {
            let p = f.expect("entry").path();
            let stem = p.file_stem().expect("stem").to_string_lossy().into_owned();
            if p.is_dir() {
                rooms.insert(stem, p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                texts.insert(stem, std::fs::read_to_string(&p).expect("readable"));
            }
        }
        let siblings: BTreeSet<String> = texts.keys().filter(|k| *k != "mod").chain(rooms.keys()).cloned().collect();
        let mut graph: BTreeMap<String, BTreeSet<String>> =
            texts.iter().map(|(f, t)| (f.clone(), sibling_uses(path, f, t, &siblings))).collect();
        for (room, room_dir) in &rooms {
            let mut used = BTreeSet::new();
            for f in files_under(room_dir) {
                let code = code_before_tests(&std::fs::read_to_string(&f).expect("readable"));
                used.extend(
                    names_after(&code, &format!("crate::{path}::")).into_iter().filter(|n| siblings.contains(n)),
                );
            }
            used.remove(room);
            graph.insert(room.clone(), used);
        }
        if let Some(c) = find_cycle(&graph) {
            circles.push(format!("src/{}/: {}", path.replace("::", "/"), c.join(" → ")));
        }
    }
    assert!(
        circles.is_empty(),
        "files or rooms of one module that use each other in a circle:\n{}",
        circles.join("\n")
    );
}

/// room of `beam` → rooms it may use, parsed from ARCHITECTURE.md's
/// "## Rooms of `beam`" table.
fn beam_rooms() -> BTreeMap<String, BTreeSet<String>> {
    table("## Rooms of `beam`", "room")
}

/// Inside `beam`, every `crate::beam::<room>` path (tests included) must be
/// allowed by the rooms table: the model never reaches a solver, the
/// references never an accelerator, and only the dispatch (`modal`) and the
/// face (`mod.rs`) use the accelerators (`fast`). Every file and folder of
/// `src/beam/` is a row.
#[test]
fn every_room_of_beam_uses_only_what_architecture_md_allows() {
    let table = beam_rooms();
    assert!(table.contains_key("fast") && table.contains_key("modal"), "table not parsed: {table:?}");
    let dir = root().join("src/beam");
    let mut violations = Vec::new();
    for f in files_under(&dir) {
        let rel = f.strip_prefix(&dir).expect("under src/beam");
        let first = rel.components().next().expect("a component").as_os_str().to_string_lossy().into_owned();
        let room = first.trim_end_matches(".rs").to_string();
        if room == "mod" {
            continue;
        }
        let Some(ok) = table.get(&room) else {
            violations.push(format!("{}: room `{room}` is not in ARCHITECTURE.md's rooms of `beam`", f.display()));
            continue;
        };
        let text = std::fs::read_to_string(&f).expect("readable");
        for (i, line) in text.lines().enumerate() {
            for used in names_after(code_of(line), "crate::beam::") {
                let module = used.chars().next().is_some_and(|c| c.is_ascii_lowercase());
                if module && used != room && !ok.contains(&used) {
                    violations.push(format!("{}:{}: room `{room}` uses `crate::beam::{used}`", f.display(), i + 1));
                }
            }
        }
    }
    assert!(violations.is_empty(), "uses the rooms table does not allow:\n{}", violations.join("\n"));
}

#[test]
fn the_circle_finder_sees_groups_and_cycles() {
    let names = names_after("use super::{a, b::{c, d}, E};\nlet x = super::f::g();", "super::");
    assert_eq!(names.into_iter().collect::<Vec<_>>(), ["E", "a", "b", "f"]);
    let siblings: BTreeSet<String> = ["a", "b"].map(String::from).into();
    let uses = sibling_uses("m", "a", "use super::b::X;\nuse super::Item;\n#[cfg(test)]\nuse super::a;", &siblings);
    assert_eq!(uses.into_iter().collect::<Vec<_>>(), ["b", "mod"]);
    let facade = sibling_uses("m", "mod", "mod a;\npub use a::X;\nfn f() { b::g() }", &siblings);
    assert_eq!(facade.into_iter().collect::<Vec<_>>(), ["b"]);
    let g = |edges: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in edges {
            g.entry(a.to_string()).or_default().insert(b.to_string());
        }
        g
    };
    assert_eq!(
        find_cycle(&g(&[("a", "b"), ("b", "c"), ("c", "a")])),
        Some(vec!["a".into(), "b".into(), "c".into(), "a".into()])
    );
    assert_eq!(find_cycle(&g(&[("a", "b"), ("b", "c"), ("a", "c")])), None);
}

/// A date (YYYY-MM-DD) or a commit hash (7–40 hex digits, with a digit and
/// a letter, after `at`, `commit`, `since`, `before` or `after`) in `line`.
fn dated(line: &str) -> Option<String> {
    let b = line.as_bytes();
    let digit = |i: usize| b.get(i).is_some_and(u8::is_ascii_digit);
    for i in 0..b.len() {
        let starts_word = i == 0 || !b[i - 1].is_ascii_alphanumeric();
        if starts_word
            && (0..4).all(|k| digit(i + k))
            && b.get(i + 4) == Some(&b'-')
            && digit(i + 5)
            && digit(i + 6)
            && b.get(i + 7) == Some(&b'-')
            && digit(i + 8)
            && digit(i + 9)
            && !digit(i + 10)
        {
            return Some(line[i..i + 10].to_string());
        }
    }
    let words: Vec<&str> = line.split(|c: char| !c.is_ascii_alphanumeric()).filter(|w| !w.is_empty()).collect();
    for w in words.windows(2) {
        let hash = w[1];
        let hexy = (7..=40).contains(&hash.len())
            && hash.chars().all(|c| c.is_ascii_digit() || ('a'..='f').contains(&c))
            && hash.chars().any(|c| c.is_ascii_digit())
            && hash.chars().any(|c| c.is_ascii_alphabetic());
        if hexy && ["at", "commit", "since", "before", "after"].contains(&w[0].to_ascii_lowercase().as_str()) {
            return Some(format!("{} {hash}", w[0]));
        }
    }
    None
}

/// Measurements (dates, commit hashes) belong in records (`tests/*.md`,
/// `benches/README.md`) and commit messages, not in `src/`.
#[test]
fn no_date_or_commit_hash_in_src() {
    let mut files = Vec::new();
    rust_files(&root().join("src"), &mut files);
    files.sort();
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).expect("readable");
        for (i, line) in text.lines().enumerate() {
            if let Some(what) = dated(line) {
                found.push(format!("{}:{}: {what}", f.display(), i + 1));
            }
        }
    }
    assert!(found.is_empty(), "dates or commit hashes in src/ (move them to a record):\n{}", found.join("\n"));
}

#[test]
fn dates_and_hashes_are_recognised() {
    assert_eq!(dated("measured 2026-11-25 on"), Some("2026-11-25".into()));
    assert_eq!(dated("(2026-11-27)").as_deref(), Some("2026-11-27"));
    assert_eq!(dated("screened, at 9bd7092)"), Some("at 9bd7092".into()));
    assert_eq!(dated("commit 5cef615a"), Some("commit 5cef615a".into()));
    assert_eq!(dated("x = 12026-11-250"), None);
    assert_eq!(dated("at 1000000 samples, at deadbeef, at 1e12"), None);
    assert_eq!(dated("let range = 2..=10;"), None);
}

/// Each package's resolved features in one cargo build context (`cargo tree
/// -e features` style, read from `--format {p}|{f}`), for the host target
/// (`cargo tree`'s default).
fn resolved_features(args: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let out = std::process::Command::new(env!("CARGO"))
        .current_dir(root())
        .args(["tree", "--locked", "--prefix", "none", "--format", "{p}|{f}"])
        .args(args)
        .output()
        .expect("cargo runs");
    assert!(out.status.success(), "cargo tree {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let mut features: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Some((package, list)) = line.trim_end_matches(" (*)").split_once('|') else { continue };
        let entry = features.entry(package.trim().to_string()).or_default();
        entry.extend(list.split(',').filter(|f| !f.is_empty()).map(str::to_string));
    }
    features
}

/// The feature-unification block of `Cargo.toml` is complete: the Python
/// extension's build (maturin: `nanobeam-py` with `extension-module`) and the
/// xtask driver's (`cargo run -p xtask`) resolve every package they share with
/// `cargo test --workspace` to the same features, so neither rebuilds the
/// core crate CI's test build made. The one difference allowed is the
/// extension's own `extension-module` feature, which only pyo3 and the
/// extension crate see.
#[test]
fn the_extension_and_xtask_builds_reuse_the_test_builds_core_crate() {
    let test = resolved_features(&["--workspace", "-e", "normal,build,dev"]);
    let contexts = [
        ("the Python extension", vec!["-p", "nanobeam-py", "--features", "nanobeam-py/extension-module"]),
        ("xtask", vec!["-p", "xtask"]),
    ];
    for (name, args) in contexts {
        let mut args = args;
        args.extend(["-e", "normal,build"]);
        let other = resolved_features(&args);
        let differ: Vec<String> = other
            .iter()
            .filter(|(p, _)| !p.starts_with("pyo3") && !p.starts_with("nanobeam-py"))
            .filter_map(|(p, f)| {
                let t = test.get(p)?;
                (t != f).then(|| format!("{p}: test build {t:?}, {name} {f:?}"))
            })
            .collect();
        assert!(
            differ.is_empty(),
            "features differ from `cargo test --workspace`; name them in Cargo.toml's unification block:\n{}",
            differ.join("\n")
        );
    }
}
