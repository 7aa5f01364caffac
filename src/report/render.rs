//! Template rendering (tera) and atomic file/directory output.

use super::error::{ReportError, Result};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Renders template `name` (a path relative to `dir`, `/`-separated) with
/// `context` (a JSON object).
///
/// Every file under `dir` (recursively) is loaded, so templates may
/// `{% extends %}`, `{% include %}` or `{% import %}` each other by their
/// relative path. Errors name the template file: a parse error names the file
/// that fails to parse; a render error names `dir/name` and carries tera's
/// whole message chain (which names an inner template when the error is there).
pub fn render_template(dir: &Path, name: &str, context: &serde_json::Value) -> Result<String> {
    let requested = dir.join(name);
    let templates = read_template_dir(dir)?;
    if !templates.iter().any(|(n, _)| n == name) {
        return Err(ReportError::Template {
            file: requested,
            message: format!("no such template in {}", dir.display()),
        });
    }
    // Parse each file on its own first so a syntax error names its file.
    for (tpl_name, content) in &templates {
        if let Err(e) = tera::Template::new(tpl_name, None, content) {
            return Err(ReportError::Template { file: dir.join(tpl_name), message: error_chain(&e) });
        }
    }
    render_set(&templates, name, context, requested)
}

/// Renders one template given as text (e.g. compiled into the binary with
/// `include_str!`, so an installed CLI needs no template directory); errors name `name`.
pub fn render_embedded(name: &str, content: &str, context: &serde_json::Value) -> Result<String> {
    render_set(&[(name.to_string(), content.to_string())], name, context, PathBuf::from(name))
}

/// Renders `name` out of the parsed set `templates`; errors name `file`.
fn render_set(
    templates: &[(String, String)],
    name: &str,
    context: &serde_json::Value,
    file: PathBuf,
) -> Result<String> {
    let mut tera = tera::Tera::default();
    tera.add_raw_templates(templates.iter().map(|(n, c)| (n.as_str(), c.as_str())))
        .map_err(|e| ReportError::Template { file: file.clone(), message: error_chain(&e) })?;
    let ctx = tera::Context::from_value(context.clone())
        .map_err(|e| ReportError::Template { file: file.clone(), message: error_chain(&e) })?;
    tera.render(name, &ctx).map_err(|e| ReportError::Template { file, message: error_chain(&e) })
}

/// `(relative name, content)` of every file under `dir`, sorted by name.
fn read_template_dir(dir: &Path) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d).map_err(|e| ReportError::io(&d, e))? {
            let path = entry.map_err(|e| ReportError::io(&d, e))?.path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let rel = path.strip_prefix(dir).expect("walked below dir");
                let name = rel.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/");
                let content = fs::read_to_string(&path).map_err(|e| ReportError::io(&path, e))?;
                out.push((name, content));
            }
        }
    }
    out.sort();
    Ok(out)
}

/// The error and all its sources, joined by ": ".
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut msg = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        msg.push_str(": ");
        msg.push_str(&s.to_string());
        source = s.source();
    }
    msg
}

static UNIQUE: AtomicU64 = AtomicU64::new(0);

/// A fresh, not yet existing sibling path of `dest`: `.<name>.<tag>-<pid>-<n>`.
fn sibling(dest: &Path, tag: &str) -> Result<PathBuf> {
    let parent = match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = dest
        .file_name()
        .ok_or_else(|| ReportError::invalid(dest.display().to_string(), "destination has no file name"))?
        .to_string_lossy();
    loop {
        let n = UNIQUE.fetch_add(1, Ordering::Relaxed);
        let candidate = parent.join(format!(".{name}.{tag}-{}-{n}", std::process::id()));
        if !candidate.exists() {
            return Ok(candidate);
        }
    }
}

/// Removes a temporary directory when dropped unless disarmed (also on panic).
struct TempDirGuard(Option<PathBuf>);

impl Drop for TempDirGuard {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = fs::remove_dir_all(p);
        }
    }
}

/// Builds an output directory in a temporary sibling of `dest`, then moves it
/// into place.
///
/// `build` receives the temporary directory and fills it. If `build` fails
/// (or panics), the temporary directory is removed and `dest` is left exactly
/// as it was. On success an existing `dest` is first renamed aside, the new
/// directory renamed to `dest`, and the old one deleted; if the second rename
/// fails the old directory is renamed back. (POSIX `rename` cannot replace a
/// non-empty directory in one step, so between the two renames — two
/// metadata operations on the same file system — `dest` briefly does not
/// exist; it never holds a partial build.)
pub fn write_dir_atomically<E>(
    dest: &Path,
    build: impl FnOnce(&Path) -> std::result::Result<(), E>,
) -> std::result::Result<(), E>
where
    E: From<ReportError>,
{
    let tmp = sibling(dest, "tmp")?;
    fs::create_dir_all(&tmp).map_err(|e| ReportError::io(&tmp, e))?;
    let mut guard = TempDirGuard(Some(tmp.clone()));
    build(&tmp)?;
    let old = if dest.exists() {
        let old = sibling(dest, "old")?;
        fs::rename(dest, &old).map_err(|e| ReportError::io(dest, e))?;
        Some(old)
    } else {
        None
    };
    if let Err(e) = fs::rename(&tmp, dest) {
        if let Some(old) = &old {
            let _ = fs::rename(old, dest);
        }
        return Err(ReportError::io(dest, e).into());
    }
    guard.0 = None;
    if let Some(old) = old {
        fs::remove_dir_all(&old).map_err(|e| ReportError::io(&old, e))?;
    }
    Ok(())
}

/// Writes `bytes` to a temporary sibling of `path` and renames it over
/// `path` (atomic on POSIX file systems); `path` is untouched on failure.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = sibling(path, "tmp")?;
    if let Err(e) = fs::write(&tmp, bytes) {
        let _ = fs::remove_file(&tmp);
        return Err(ReportError::io(&tmp, e));
    }
    fs::rename(&tmp, path).map_err(|e| {
        let _ = fs::remove_file(&tmp);
        ReportError::io(path, e)
    })
}
