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

/// The file that marks a directory as written by nanobeam: only such a
/// directory (or an empty one) is ever replaced by [`write_dir_atomically`].
pub const MARKER_FILE: &str = ".nanobeam-output";

/// Temporary siblings of `dest` are `.<name>.<tag>-<pid>-<n>`; these tags.
const TAGS: [&str; 3] = ["tmp", "old", "probe"];

fn parent_of(dest: &Path) -> PathBuf {
    match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn file_name_of(dest: &Path) -> Result<String> {
    dest.file_name().map(|n| n.to_string_lossy().into_owned()).filter(|n| n != "." && n != "..").ok_or_else(|| {
        ReportError::OutPath {
            path: dest.to_path_buf(),
            reason: "it has no final file name (use a path like DIR/results)".into(),
        }
    })
}

/// A fresh, not yet existing sibling path of `dest`: `.<name>.<tag>-<pid>-<n>`.
fn sibling(dest: &Path, tag: &str) -> Result<PathBuf> {
    let parent = parent_of(dest);
    let name = file_name_of(dest)?;
    loop {
        let n = UNIQUE.fetch_add(1, Ordering::Relaxed);
        let candidate = parent.join(format!(".{name}.{tag}-{}-{n}", std::process::id()));
        if fs::symlink_metadata(&candidate).is_err() {
            return Ok(candidate);
        }
    }
}

/// Checks, before any computation, that `dest` can take an output directory:
/// it is absent, an empty directory, or a directory carrying [`MARKER_FILE`]
/// (never a file, a symbolic link or someone else's non-empty directory), and
/// its parent (or nearest existing ancestor) is a writable directory — probed
/// by creating and removing a temporary sibling. Also removes temporary
/// siblings left by processes that no longer run (and puts back an output a
/// dead process had moved aside). Installs the SIGINT/SIGTERM cleanup first,
/// so that a signal during the probe leaves nothing behind.
pub fn check_out_dir(dest: &Path) -> Result<()> {
    let name = file_name_of(dest)?;
    check_dest(dest)?;
    let refuse = |reason: &str| Err(ReportError::OutPath { path: dest.to_path_buf(), reason: reason.to_string() });
    let parent = parent_of(dest);
    let mut existing = parent.clone();
    while fs::symlink_metadata(&existing).is_err() {
        match existing.parent() {
            Some(p) if !p.as_os_str().is_empty() => existing = p.to_path_buf(),
            _ => existing = PathBuf::from("."),
        }
        if existing == Path::new(".") {
            break;
        }
    }
    if !existing.is_dir() {
        return refuse(&format!("{} is not a directory", existing.display()));
    }
    if existing == parent {
        recover_stale(&parent, &name, dest);
    }
    // The cleanup is installed before the probe exists, and the probe lives
    // only while the cleanup lock is held: a signal at any instant finds no
    // probe (the handler waits for the lock), so none is left behind.
    signals::install();
    let _hold = signals::lock();
    let probe = sibling(&existing.join(&name), "probe")?;
    fs::create_dir(&probe).map_err(|e| ReportError::OutPath {
        path: dest.to_path_buf(),
        reason: format!("{} is not writable ({e})", existing.display()),
    })?;
    let _ = fs::remove_dir(&probe);
    Ok(())
}

/// Removes `.<name>.<tag>-<pid>-<n>` siblings whose process is gone; an
/// `old` one is renamed back to `dest` when `dest` is missing (a writer using
/// two renames died between them).
fn recover_stale(parent: &Path, name: &str, dest: &Path) {
    let Ok(entries) = fs::read_dir(parent) else { return };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&format!(".{name}.")) else { continue };
        let Some((tag, ids)) = rest.split_once('-') else { continue };
        let Some(pid) = ids.split('-').next().and_then(|p| p.parse::<i32>().ok()) else { continue };
        if !TAGS.contains(&tag) || process_alive(pid) {
            continue;
        }
        let path = entry.path();
        if tag == "old" && fs::symlink_metadata(dest).is_err() && fs::rename(&path, dest).is_ok() {
            continue;
        }
        remove_any(&path);
    }
}

/// Removes a temporary path, a directory (with its contents) or a file.
fn remove_any(path: &Path) {
    match fs::symlink_metadata(path) {
        Ok(meta) if meta.is_dir() => {
            let _ = fs::remove_dir_all(path);
        }
        Ok(_) => {
            let _ = fs::remove_file(path);
        }
        Err(_) => {}
    }
}

/// Whether process `pid` exists (`kill(pid, 0)`: success or EPERM).
fn process_alive(pid: i32) -> bool {
    if pid <= 0 {
        return false;
    }
    // SAFETY: signal 0 only checks for existence and permission.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// Cleanup on SIGINT/SIGTERM (signal-hook's iterator thread): temporary
/// paths are registered while they exist; the handler thread takes the same
/// lock that every [`write_dir_atomically`] holds from creating its temporary
/// directory to the end of its swap, so it acts only between writes (the
/// output is then either the old or the new complete directory), removes what
/// is registered, and exits with 128 + signal.
mod signals {
    use std::path::PathBuf;
    use std::sync::{Mutex, MutexGuard, Once};

    static WRITE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
    static INSTALL: Once = Once::new();

    pub(super) fn lock() -> MutexGuard<'static, Vec<PathBuf>> {
        WRITE.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(super) fn install() {
        INSTALL.call_once(|| {
            let Ok(mut signals) =
                signal_hook::iterator::Signals::new([signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM])
            else {
                return; // default disposition: the process dies; stale siblings are recovered next time
            };
            std::thread::spawn(move || {
                if let Some(sig) = signals.forever().next() {
                    let pending = lock();
                    for p in pending.iter() {
                        super::remove_any(p);
                    }
                    std::process::exit(128 + sig);
                }
            });
        });
    }
}

/// Exchanges two paths atomically (Linux `renameat2(RENAME_EXCHANGE)`);
/// `false` where unsupported (the caller then uses two renames).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> bool {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let (Ok(ca), Ok(cb)) = (CString::new(a.as_os_str().as_bytes()), CString::new(b.as_os_str().as_bytes())) else {
        return false;
    };
    // SAFETY: two valid NUL-terminated paths relative to the current directory.
    unsafe { libc::renameat2(libc::AT_FDCWD, ca.as_ptr(), libc::AT_FDCWD, cb.as_ptr(), libc::RENAME_EXCHANGE) == 0 }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_a: &Path, _b: &Path) -> bool {
    false
}

/// One write in progress: holds the cleanup lock (see `signals`) and removes
/// its temporary directory when dropped unless disarmed (also on panic).
struct WriteSession {
    pending: std::sync::MutexGuard<'static, Vec<PathBuf>>,
    tmp: Option<PathBuf>,
}

impl Drop for WriteSession {
    fn drop(&mut self) {
        if let Some(p) = self.tmp.take() {
            let _ = fs::remove_dir_all(&p);
            self.pending.retain(|q| q != &p);
        }
    }
}

/// Builds an output directory in a temporary sibling of `dest`, then moves it
/// into place.
///
/// `dest` is first checked by [`check_out_dir`] (callers should also call
/// that before computing, so a bad `--out` costs nothing). `build` receives
/// the temporary directory (already holding [`MARKER_FILE`]) and fills it. If
/// `build` fails or panics, the temporary directory is removed and `dest` is
/// left exactly as it was. On success the new directory replaces `dest` by one
/// atomic exchange (Linux `renameat2`), so at every instant `dest` is either
/// the old or the new complete directory; the old one is then deleted. Writers
/// in several processes take an exclusive `flock` on the parent directory for
/// the swap, so concurrent writers to one `dest` all succeed and the last
/// swap wins: one complete result. SIGINT/SIGTERM wait for the write to end
/// (see `signals`), so no temporary directory survives them.
pub fn write_dir_atomically<E>(
    dest: &Path,
    build: impl FnOnce(&Path) -> std::result::Result<(), E>,
) -> std::result::Result<(), E>
where
    E: From<ReportError>,
{
    check_out_dir(dest)?;
    let mut session = WriteSession { pending: signals::lock(), tmp: None };
    let tmp = sibling(dest, "tmp")?;
    session.pending.push(tmp.clone());
    if let Err(e) = fs::create_dir_all(&tmp) {
        session.pending.retain(|p| p != &tmp);
        return Err(ReportError::io(&tmp, e).into());
    }
    session.tmp = Some(tmp.clone());
    fs::write(tmp.join(MARKER_FILE), "written by nanobeam; replaced as a whole by the next run\n")
        .map_err(|e| ReportError::io(&tmp, e))?;
    build(&tmp)?;
    let parent = parent_of(dest);
    let lock = fs::File::open(&parent).map_err(|e| ReportError::io(&parent, e))?;
    lock.lock().map_err(|e| ReportError::io(&parent, e))?;
    // re-checked under the lock: another process may have put something there
    check_dest(dest)?;
    match fs::symlink_metadata(dest) {
        // `tmp` now holds the old output: the session removes it on drop
        Ok(_) if exchange(&tmp, dest) => {}
        Ok(_) => {
            let old = sibling(dest, "old")?;
            session.pending.push(old.clone());
            fs::rename(dest, &old).map_err(|e| ReportError::io(dest, e))?;
            if let Err(e) = fs::rename(&tmp, dest) {
                let _ = fs::rename(&old, dest);
                session.pending.retain(|p| p != &old);
                return Err(ReportError::io(dest, e).into());
            }
            session.tmp = None;
            session.pending.retain(|p| p != &tmp);
            let _ = fs::remove_dir_all(&old);
            session.pending.retain(|p| p != &old);
        }
        Err(_) => {
            fs::rename(&tmp, dest).map_err(|e| ReportError::io(dest, e))?;
            session.tmp = None;
            session.pending.retain(|p| p != &tmp);
        }
    }
    drop(session);
    drop(lock);
    Ok(())
}

/// The destination part of [`check_out_dir`] (repeated under the swap lock).
fn check_dest(dest: &Path) -> Result<()> {
    let refuse = |reason: &str| Err(ReportError::OutPath { path: dest.to_path_buf(), reason: reason.to_string() });
    match fs::symlink_metadata(dest) {
        Ok(meta) if meta.file_type().is_symlink() => refuse("it is a symbolic link (give the real directory)"),
        Ok(meta) if !meta.is_dir() => refuse("it is an existing file, not a directory"),
        Ok(_) => {
            let mut entries = fs::read_dir(dest).map_err(|e| ReportError::io(dest, e))?;
            if entries.next().is_some() && !dest.join(MARKER_FILE).is_file() {
                refuse(&format!(
                    "it is a non-empty directory not written by nanobeam (no {MARKER_FILE}); choose a new path"
                ))
            } else {
                Ok(())
            }
        }
        Err(_) => Ok(()),
    }
}

/// Checks, before any computation, that `dest` can take an output file:
/// it is not a directory or a symbolic link, and its parent is an existing
/// writable directory (probed by creating and removing a temporary sibling).
/// Also removes temporary siblings of `dest` left by processes that no longer
/// run, and installs the SIGINT/SIGTERM cleanup. Errors are
/// [`ReportError::OutPath`] (a bad `--out`, exit 2).
pub fn check_out_file(dest: &Path) -> Result<()> {
    let name = file_name_of(dest)?;
    let refuse = |reason: String| Err(ReportError::OutPath { path: dest.to_path_buf(), reason });
    match fs::symlink_metadata(dest) {
        Ok(meta) if meta.file_type().is_symlink() => {
            return refuse("it is a symbolic link (give the real file)".into())
        }
        Ok(meta) if meta.is_dir() => return refuse("it is an existing directory, not a file".into()),
        _ => {}
    }
    let parent = parent_of(dest);
    if !parent.is_dir() {
        return refuse(format!("its parent {} is not an existing directory", parent.display()));
    }
    recover_stale(&parent, &name, dest);
    signals::install();
    let _hold = signals::lock();
    let probe = sibling(dest, "probe")?;
    fs::create_dir(&probe).map_err(|e| ReportError::OutPath {
        path: dest.to_path_buf(),
        reason: format!("{} is not writable ({e})", parent.display()),
    })?;
    let _ = fs::remove_dir(&probe);
    Ok(())
}

/// A file written in full to a temporary sibling of its destination and
/// registered with the SIGINT/SIGTERM cleanup: [`StagedFile::commit`] renames
/// it into place; dropping it uncommitted (an error elsewhere, a panic)
/// removes it, and so does a signal. Lets a command write several outputs
/// all or nothing: stage the file, write the rest, then commit.
pub struct StagedFile {
    tmp: Option<PathBuf>,
    dest: PathBuf,
}

impl StagedFile {
    /// Writes `bytes` to a fresh temporary sibling of `dest`.
    pub fn new(dest: &Path, bytes: &[u8]) -> Result<Self> {
        signals::install();
        let tmp = {
            let mut pending = signals::lock();
            let tmp = sibling(dest, "tmp")?;
            pending.push(tmp.clone());
            tmp
        };
        let staged = StagedFile { tmp: Some(tmp.clone()), dest: dest.to_path_buf() };
        // on failure `staged` is dropped, which removes the partial file
        fs::write(&tmp, bytes).map_err(|e| ReportError::io(dest, e))?;
        Ok(staged)
    }

    /// Renames the staged file over the destination (atomic on POSIX file
    /// systems), under the cleanup lock so a signal sees it either staged
    /// (and removes it) or in place.
    pub fn commit(mut self) -> Result<()> {
        let tmp = self.tmp.take().expect("a staged file has its temporary path until committed or dropped");
        let mut pending = signals::lock();
        let renamed = fs::rename(&tmp, &self.dest);
        if renamed.is_err() {
            let _ = fs::remove_file(&tmp);
        }
        pending.retain(|p| p != &tmp);
        renamed.map_err(|e| ReportError::io(&self.dest, e))
    }
}

impl Drop for StagedFile {
    fn drop(&mut self) {
        if let Some(tmp) = self.tmp.take() {
            let mut pending = signals::lock();
            let _ = fs::remove_file(&tmp);
            pending.retain(|p| p != &tmp);
        }
    }
}

/// Writes `bytes` to a temporary sibling of `path` and renames it over
/// `path` (atomic on POSIX file systems); `path` is untouched on failure, and
/// SIGINT/SIGTERM during the write leave no temporary file (see
/// [`StagedFile`]). Not for use inside [`write_dir_atomically`]'s `build`
/// (which holds the cleanup lock and whose directory is already temporary).
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    StagedFile::new(path, bytes)?.commit()
}
