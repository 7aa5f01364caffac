//! `nanobeam._nanobeam`: the compiled half of the Python package (PyO3).
//!
//! Each function mirrors one CLI command of `nanobeam::cli` and calls the
//! library the way that command does, so its numbers, its seeds' draws and
//! its error lines are the CLI's. Results cross into Python as JSON text (the
//! structures the CLI prints with `--json`) or as little-endian `f64` bytes
//! (numpy arrays); the Python half (`nanobeam/__init__.py`) turns them into
//! dicts, numpy arrays and `arviz.InferenceData`.
//!
//! Conventions: bad input raises `ValueError` with the CLI's one-line message
//! ([`CliError::Input`]); a numerical or output failure raises
//! `nanobeam.NumericalError` ([`CliError::Failure`]). The work runs on a
//! worker thread while the calling thread waits without the GIL, checks
//! Python's signals every 50 ms, cancels the library's [`Control`] on
//! Ctrl-C and hands the worker's progress counts to a Python callback
//! (`run_interruptible`).

use std::path::{Path, PathBuf};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use nanobeam::bayes::{Control, Progress};
use nanobeam::beam::{frf_each, modal, BeamError, BeamSpec};
use nanobeam::calibration::output::{inference_data, InferenceContext};
use nanobeam::calibration::{calibrate, BeamPosterior, CalibrateOptions, MeasuredData};
use nanobeam::cli::{self, campaign, CliError};
use nanobeam::error::InputError;
use nanobeam::report::inference_data::InferenceData;
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

create_exception!(
    _nanobeam,
    NumericalError,
    PyException,
    "A numerical failure on valid input (the CLI's exit code 1): a solver that did not converge, \
     chains that cannot sample, a model that fails at every prior draw."
);

/// How often the waiting thread looks at Python's signals (Ctrl-C): short
/// enough to feel immediate, long enough to cost nothing.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Stack of the worker thread: the size of a main thread's on Linux, which
/// is what the CLI runs the same code on.
const WORKER_STACK: usize = 8 << 20;

fn to_py(e: CliError) -> PyErr {
    match e {
        CliError::Input(_) => PyValueError::new_err(e.to_string()),
        CliError::Failure(_) => NumericalError::new_err(e.to_string()),
    }
}

/// The progress a worker reports ([`Progress`]), kept for the waiting
/// thread: the worker only stores counts (it never touches Python), and the
/// waiting thread, which holds the GIL between its waits, hands them to the
/// Python callback.
#[derive(Default)]
struct Counts {
    state: Mutex<PhaseCounts>,
}

/// The current phase: its number (a new phase is a new bar), unit, size and
/// units done.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
struct PhaseCounts {
    phase: u64,
    unit: &'static str,
    total: u64,
    done: u64,
}

impl Counts {
    fn get(&self) -> PhaseCounts {
        *self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Progress for Counts {
    fn start(&self, unit: &'static str, total: u64) {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        *s = PhaseCounts { phase: s.phase + 1, unit, total, done: 0 };
    }

    fn advance(&self, n: u64) {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        s.done = (s.done + n).min(s.total);
    }

    /// Nothing to do: the Python side closes its bar when the call returns.
    fn finish(&self) {}
}

/// Hands the counts to `callback(unit, done, total)` when they changed since
/// `last` (on the calling thread, with the GIL).
fn report(py: Python<'_>, callback: Option<&PyObject>, counts: &Counts, last: &mut PhaseCounts) -> PyResult<()> {
    let Some(cb) = callback else { return Ok(()) };
    let now = counts.get();
    if now != *last && now.phase > 0 {
        *last = now;
        cb.call1(py, (now.unit, now.done, now.total))?;
    }
    Ok(())
}

/// How a call's work is controlled from Python.
enum Interrupt {
    /// The library polls a [`Control`]: Ctrl-C cancels it, and the call
    /// returns once the worker has stopped.
    Cancel,
    /// Work without cancellation points (modal, frf: seconds at
    /// most on valid input): Ctrl-C returns at once, the worker finishes in
    /// the background and its result is dropped.
    Abandon,
}

/// Runs `work` on a worker thread; the calling thread releases the GIL and
/// waits, checking Python's signals (and reporting progress to `callback`)
/// every [`SIGNAL_POLL`].
///
/// A pending `KeyboardInterrupt` (or any exception a signal handler or the
/// callback raises) with [`Interrupt::Cancel`] cancels the worker's
/// [`Control`] and waits for the worker to stop (the samplers poll it at
/// every step; [`nanobeam::bayes::control`]), then raises; a second signal
/// during that wait raises at once and leaves the worker to stop alone.
/// Nothing the library computes is written anywhere, so a cancelled call
/// leaves nothing behind.
fn run_interruptible<T, F>(py: Python<'_>, interrupt: Interrupt, callback: Option<PyObject>, work: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce(Control) -> Result<T, CliError> + Send + 'static,
{
    let counts = Arc::new(Counts::default());
    let control = Control::with_progress(counts.clone());
    let (tx, rx) = mpsc::channel();
    let worker_control = control.clone();
    let handle = std::thread::Builder::new()
        .name("nanobeam".into())
        .stack_size(WORKER_STACK)
        .spawn(move || {
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || work(worker_control)));
            // The receiver is gone only after an abandoning interrupt: the result is not wanted.
            let _ = tx.send(result);
        })
        .map_err(|e| NumericalError::new_err(format!("error: cannot start a worker thread: {e}")))?;
    let mut rx = rx;
    let mut last = PhaseCounts::default();
    let mut interrupted: Option<PyErr> = None;
    loop {
        // moved in and out: a `Receiver` is `Send` but not `Sync`
        let (back, received) = py.allow_threads(move || {
            let r = rx.recv_timeout(SIGNAL_POLL);
            (rx, r)
        });
        rx = back;
        let result = match received {
            Ok(result) => result,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                let polled = if interrupted.is_none() {
                    report(py, callback.as_ref(), &counts, &mut last).and_then(|()| py.check_signals())
                } else {
                    py.check_signals()
                };
                if let Err(e) = polled {
                    match (&interrupt, interrupted.is_some()) {
                        (Interrupt::Cancel, false) => {
                            control.cancel();
                            interrupted = Some(e);
                        }
                        // a second interrupt while waiting, or nothing to wait for
                        _ => return Err(e),
                    }
                }
                continue;
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(NumericalError::new_err("error: internal failure: the worker thread vanished"))
            }
        };
        // the worker has sent its result: let it end, so no thread of this call outlives it
        let _ = py.allow_threads(move || handle.join());
        if let Some(e) = interrupted {
            return Err(e);
        }
        report(py, callback.as_ref(), &counts, &mut last)?;
        return match result {
            Ok(result) => result.map_err(to_py),
            Err(panic) => {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                Err(NumericalError::new_err(format!("error: internal failure: {what}")))
            }
        };
    }
}

/// Where a YAML document comes from: a path (read as the CLI reads it) or
/// the text the Python side made of a dict.
enum Source {
    Path(PathBuf),
    Text(String),
}

impl Source {
    fn new(path: Option<String>, text: Option<String>, what: &str) -> PyResult<Self> {
        match (path, text) {
            (Some(p), None) => Ok(Source::Path(p.into())),
            (None, Some(t)) => Ok(Source::Text(t)),
            _ => Err(PyValueError::new_err(format!("invalid {what}: allowed a path or a dict"))),
        }
    }

    fn beam(&self) -> Result<BeamSpec, CliError> {
        match self {
            Source::Path(p) => cli::read_beam(p),
            Source::Text(t) => BeamSpec::from_yaml(t).map_err(|e| CliError::Input(cli::name_serde_value(e))),
        }
    }

    fn measured(&self) -> Result<MeasuredData, CliError> {
        match self {
            Source::Path(p) => cli::read_measured(p),
            Source::Text(t) => MeasuredData::from_yaml(t).map_err(|e| CliError::Input(cli::name_serde_value(e))),
        }
    }
}

/// `nanobeam modal BEAM.yaml --modes K --json`: the JSON text.
#[pyfunction]
#[pyo3(signature = (beam_path, beam_text, modes))]
fn modal_json(py: Python<'_>, beam_path: Option<String>, beam_text: Option<String>, modes: usize) -> PyResult<String> {
    let source = Source::new(beam_path, beam_text, "beam")?;
    run_interruptible(py, Interrupt::Abandon, None, move |_| {
        let beam = source.beam()?;
        let dofs = beam.free_dofs();
        if modes == 0 || modes > dofs {
            return Err(InputError::new(
                "--modes",
                modes,
                format!("1..={dofs} (physical modes of this mesh: its free DOFs)"),
            )
            .into());
        }
        let result = modal(&beam, modes)?;
        Ok(cli::modal::json(&result))
    })
}

fn f64_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// `nanobeam frf`: (ω, Re H, Im H) as little-endian f64 bytes.
#[pyfunction]
#[pyo3(signature = (beam_path, beam_text, input_x_nm, output_x_nm, from_rad_s, to_rad_s, points, log))]
#[allow(clippy::too_many_arguments)]
fn frf_arrays(
    py: Python<'_>,
    beam_path: Option<String>,
    beam_text: Option<String>,
    input_x_nm: f64,
    output_x_nm: f64,
    from_rad_s: f64,
    to_rad_s: f64,
    points: usize,
    log: bool,
) -> PyResult<(Py<PyBytes>, Py<PyBytes>, Py<PyBytes>)> {
    let source = Source::new(beam_path, beam_text, "beam")?;
    let args = cli::frf::FrfArgs {
        beam: PathBuf::new(),
        input_x_nm,
        output_x_nm,
        from_rad_s,
        to_rad_s,
        points,
        log,
        json: false,
        csv: false,
    };
    let (w, re, im) = run_interruptible(py, Interrupt::Abandon, None, move |_| {
        // the CLI's order: the beam, the grid, the frequency bound, then the solves
        let beam = source.beam()?;
        let grid = cli::frf::grid(&args)?;
        cli::frf::check_top_frequency(&beam, args.to_rad_s)?;
        let (mut re, mut im) = (Vec::with_capacity(grid.len()), Vec::with_capacity(grid.len()));
        frf_each(&beam, args.input_x_nm, args.output_x_nm, grid.iter().copied(), |_, z| {
            re.push(z.re);
            im.push(z.im);
            Ok::<(), BeamError>(())
        })?;
        Ok((f64_bytes(&grid), f64_bytes(&re), f64_bytes(&im)))
    })?;
    Ok((PyBytes::new(py, &w).unbind(), PyBytes::new(py, &re).unbind(), PyBytes::new(py, &im).unbind()))
}

/// One variable for Python: name, dimensions (name, length), values as f64 bytes.
type PyVariable = (String, Vec<(String, usize)>, Py<PyBytes>);
/// String attributes: (name, value).
type Attributes = Vec<(String, String)>;
/// One group for Python: name, attributes, variables.
type PyGroup = (String, Attributes, Vec<PyVariable>);
/// A calibration for Python: the `--json` summary, the groups, the root attributes.
type PyCalibration = (String, Vec<PyGroup>, Attributes);

fn groups_to_py(py: Python<'_>, idata: &InferenceData) -> Vec<PyGroup> {
    idata
        .groups
        .iter()
        .map(|g| {
            let vars = g
                .variables
                .iter()
                .map(|v| (v.name.clone(), v.dims.clone(), PyBytes::new(py, &f64_bytes(&v.values)).unbind()))
                .collect();
            (g.name.clone(), g.attributes.clone(), vars)
        })
        .collect()
}

/// `nanobeam calibrate MEASURED.yaml --json --out DIR`: the `--json` summary
/// text, and the groups and root attributes of `inference_data.nc`.
#[pyfunction]
#[pyo3(signature = (measured_path, measured_text, progress))]
fn calibrate_groups(
    py: Python<'_>,
    measured_path: Option<String>,
    measured_text: Option<String>,
    progress: Option<PyObject>,
) -> PyResult<PyCalibration> {
    let source = Source::new(measured_path, measured_text, "measured")?;
    let (summary, idata) = run_interruptible(py, Interrupt::Cancel, progress, move |control| {
        let data = source.measured()?;
        let result = calibrate(&data, &CalibrateOptions { control })?;
        let posterior = BeamPosterior::new(&data, data.parameters.clone());
        let ctx = InferenceContext { posterior: &posterior, seed: data.sampler.seed };
        let idata = inference_data(&result, &ctx);
        idata.validate()?;
        let summary = serde_json::to_string(&result.json()).expect("summary serialises");
        Ok((summary, idata))
    })?;
    let groups = groups_to_py(py, &idata);
    Ok((summary, groups, idata.attributes))
}

/// `nanobeam diagnose MEASURED.yaml --json [--samples N] [--thorough] [--max-causes K]`: the JSON text.
#[pyfunction]
#[pyo3(signature = (measured_path, measured_text, samples, thorough, max_causes, progress))]
fn diagnose_json(
    py: Python<'_>,
    measured_path: Option<String>,
    measured_text: Option<String>,
    samples: Option<usize>,
    thorough: bool,
    max_causes: Option<usize>,
    progress: Option<PyObject>,
) -> PyResult<String> {
    let source = Source::new(measured_path, measured_text, "measured")?;
    run_interruptible(py, Interrupt::Cancel, progress, move |control| {
        let args = cli::diagnose::DiagnoseArgs {
            measured: PathBuf::new(),
            out: None,
            json: true,
            samples,
            thorough,
            quick: false,
            max_causes,
        };
        // the CLI's order: the settings, then the file
        let mut settings = cli::diagnose::settings(&args);
        settings.validate()?;
        settings.control = control;
        let data = source.measured()?;
        let run = nanobeam::diagnose::diagnose_run(&data, &settings)?;
        Ok(serde_json::to_string(&run.diagnosis).expect("plain data"))
    })
}

/// `nanobeam identify DATA.csv --beam BEAM.yaml`: `{"measured": <the
/// measured-data file>, "identification": <the `--json` output>, "warnings":
/// [<each line the CLI prints after `warning: `>]}` as JSON text.
#[pyfunction]
#[pyo3(signature = (data_path, data_text, beam_path, beam_text, modes, first_mode, max_order))]
#[allow(clippy::too_many_arguments)]
fn identify_json(
    py: Python<'_>,
    data_path: Option<String>,
    data_text: Option<String>,
    beam_path: Option<String>,
    beam_text: Option<String>,
    modes: Option<usize>,
    first_mode: Option<usize>,
    max_order: usize,
) -> PyResult<String> {
    let beam_source = Source::new(beam_path, beam_text, "beam")?;
    let data_source = Source::new(data_path, data_text, "data")?;
    run_interruptible(py, Interrupt::Cancel, None, move |control| {
        if max_order < 4 {
            return Err(InputError::new("--max-order", max_order, ">= 4").into());
        }
        let beam = beam_source.beam()?;
        cli::identify::check_first_mode(first_mode, &beam)?;
        let text = match &data_source {
            Source::Path(p) => read_csv(p)?,
            Source::Text(t) => t.clone(),
        };
        // the CLI's own identification, numbering and checks
        let cli::identify::Identified { identification: id, observations, file, numbering_warning } =
            cli::identify::identify_record(beam, &text, modes, max_order, first_mode, &control)?;
        // the CLI's `warning:` lines, without the prefix (issued as Python warnings)
        let warnings: Vec<String> = nanobeam::identify::thermal::fit_warning(&text, &id.x, id.noise_sd)
            .into_iter()
            .chain(numbering_warning)
            .collect();
        let doc = serde_json::json!({
            "measured": file,
            "identification": { "modes": observations, "identification": id },
            "warnings": warnings,
        });
        Ok(serde_json::to_string(&doc).expect("plain data"))
    })
}

fn read_csv(path: &Path) -> Result<String, CliError> {
    cli::identify::read_record(path)
}

/// `nanobeam campaign`'s plan of `source` (a manifest CSV or a folder) with
/// the table at `out` (if any) read back: `{"total": n, "tasks": [<records to
/// run>], "kept": [<rows of the table that are current>]}` as JSON text. A
/// malformed manifest or a foreign `out` file raises `ValueError` (the CLI's
/// exit 2 line).
#[pyfunction]
#[pyo3(signature = (source, beam, samples, max_causes, thorough, out))]
fn campaign_plan(
    py: Python<'_>,
    source: String,
    beam: Option<String>,
    samples: Option<usize>,
    max_causes: Option<usize>,
    thorough: bool,
    out: Option<String>,
) -> PyResult<String> {
    run_interruptible(py, Interrupt::Abandon, None, move |_| {
        let out = out.map(PathBuf::from);
        let existing = match &out {
            Some(path) => campaign::table::read(path)?,
            None => vec![],
        };
        let defaults = campaign::Defaults { beam: beam.map(PathBuf::from), samples, max_causes, thorough };
        let tasks = campaign::manifest::plan(Path::new(&source), &defaults, out.as_deref())?;
        let total = tasks.len();
        let (todo, kept) = campaign::resume(tasks, &existing);
        let doc = serde_json::json!({ "total": total, "tasks": todo, "kept": kept });
        Ok(serde_json::to_string(&doc).expect("plain data"))
    })
}

/// One record of a campaign (a task of [`campaign_plan`], as JSON text): its
/// table row as JSON text. A record's failure is its row's `error`, never an
/// exception; Ctrl-C cancels the record and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (task_json, progress=None))]
fn campaign_record(py: Python<'_>, task_json: String, progress: Option<PyObject>) -> PyResult<String> {
    let task: campaign::Task = serde_json::from_str(&task_json)
        .map_err(|e| PyValueError::new_err(format!("invalid task = (JSON): allowed a task of campaign_plan ({e})")))?;
    run_interruptible(py, Interrupt::Cancel, progress, move |control| {
        let row = campaign::record::run(&task, &control);
        if control.is_cancelled() {
            return Err(CliError::Failure("cancelled".into()));
        }
        Ok(serde_json::to_string(&row).expect("plain data"))
    })
}

/// The campaign table's CSV text of `rows_json` (a JSON list of rows), in manifest order.
#[pyfunction]
fn campaign_csv(rows_json: &str) -> PyResult<String> {
    let rows: Vec<campaign::Row> = serde_json::from_str(rows_json)
        .map_err(|e| PyValueError::new_err(format!("invalid rows = (JSON): allowed rows of campaign_record ({e})")))?;
    Ok(campaign::table::to_csv(&rows))
}

/// Writes the campaign table of `rows_json` at `out`, atomically (as the CLI's `--out`).
#[pyfunction]
fn campaign_write(py: Python<'_>, out: String, rows_json: String) -> PyResult<()> {
    let rows: Vec<campaign::Row> = serde_json::from_str(&rows_json)
        .map_err(|e| PyValueError::new_err(format!("invalid rows = (JSON): allowed rows of campaign_record ({e})")))?;
    run_interruptible(py, Interrupt::Abandon, None, move |_| campaign::table::write(Path::new(&out), &rows))
}

/// YAML text → JSON text (for reading the CLI's YAML output in tests and
/// examples without a YAML package).
#[pyfunction]
fn yaml_to_json(text: &str) -> PyResult<String> {
    let value: serde_json::Value =
        nanobeam::error::parse_yaml(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(value.to_string())
}

#[pymodule]
fn _nanobeam(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NumericalError", m.py().get_type::<NumericalError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(modal_json, m)?)?;
    m.add_function(wrap_pyfunction!(frf_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_groups, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_json, m)?)?;
    m.add_function(wrap_pyfunction!(identify_json, m)?)?;
    m.add_function(wrap_pyfunction!(campaign_plan, m)?)?;
    m.add_function(wrap_pyfunction!(campaign_record, m)?)?;
    m.add_function(wrap_pyfunction!(campaign_csv, m)?)?;
    m.add_function(wrap_pyfunction!(campaign_write, m)?)?;
    m.add_function(wrap_pyfunction!(yaml_to_json, m)?)?;
    Ok(())
}
