//! Tidy: the dependency table of ARCHITECTURE.md ("## Dependencies") is the
//! law of `src/`. Every `crate::<module>` path in a module's files (imports
//! and inline paths alike, comments excluded) must be allowed by the table.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// module → modules it may use, parsed from the table.
fn allowed() -> BTreeMap<String, BTreeSet<String>> {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let section = text.split("## Dependencies").nth(1).expect("a '## Dependencies' section");
    let mut table = BTreeMap::new();
    for line in section.lines().skip_while(|l| !l.starts_with("| module")).skip(2) {
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
