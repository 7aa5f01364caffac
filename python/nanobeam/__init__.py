"""nanobeam from Python: nonlocal viscoelastic nanobeams.

The functions mirror the ``nanobeam`` command line and call the same Rust
library, so the same input and seed give the same numbers, bit for bit:

* :func:`modal` -- ``nanobeam modal BEAM.yaml --json``;
* :func:`frf` -- ``nanobeam frf ...`` as numpy arrays;
* :func:`calibrate` -- ``nanobeam calibrate MEASURED.yaml``: the groups of
  ``inference_data.nc`` as an ``arviz.InferenceData`` built in memory (a dict
  of numpy arrays when ArviZ is not installed);
* :func:`diagnose` -- ``nanobeam diagnose MEASURED.yaml --json``;
* :func:`identify` -- ``nanobeam identify DATA.csv --beam BEAM.yaml``: the
  measured-data structure, ready for :func:`calibrate` and :func:`diagnose`;
* :func:`campaign` -- ``nanobeam campaign MANIFEST --out TABLE.csv``: many
  records to one pandas DataFrame, locally or on a Dask cluster (``client=``).

Inputs are the documented YAML structures as Python dicts (lengths in nm,
everything else SI, the unit in every field name) or paths to the files.

Errors: bad input raises ``ValueError`` with the one line the CLI prints
(exit code 2); a numerical failure raises :class:`NumericalError` (exit code 1).
The work runs without the GIL. Ctrl-C during :func:`calibrate` or
:func:`diagnose` cancels the computation: ``KeyboardInterrupt`` is raised once
the library has stopped (its samplers poll a cancellation flag at every step).
Both take ``progress=``: a bar (``tqdm.auto`` when installed, else a text
line on stderr), a callable, or nothing; see :func:`calibrate`.
"""

from __future__ import annotations

import json
import os
import sys
import warnings
from collections.abc import Mapping
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

from . import _nanobeam
from ._nanobeam import NumericalError, __version__
from ._campaign import campaign

__all__ = ["modal", "frf", "calibrate", "diagnose", "identify", "campaign", "read_yaml", "NumericalError", "__version__"]

PathOrDict = Union[str, "os.PathLike[str]", Mapping]
ProgressArg = Union[None, bool, Callable[[str, int, int], Any]]


class _TextBar:
    """Progress as one text line on stderr, rewritten in place (``\\r``):
    what ``progress=True`` draws when tqdm is not installed."""

    def __init__(self) -> None:
        self._open = False

    def __call__(self, unit: str, done: int, total: int) -> None:
        sys.stderr.write(f"\r{done}/{total} {unit}")
        sys.stderr.flush()
        self._open = True

    def close(self) -> None:
        if self._open:
            sys.stderr.write("\n")
            sys.stderr.flush()
            self._open = False


class _TqdmBar:
    """Progress as ``tqdm.auto`` bars (a notebook widget in Jupyter), one per phase."""

    def __init__(self, tqdm) -> None:
        self._tqdm = tqdm
        self._bar = None
        self._phase: Optional[Tuple[str, int]] = None

    def __call__(self, unit: str, done: int, total: int) -> None:
        if self._bar is None or self._phase != (unit, total):
            self.close()
            self._bar = self._tqdm(total=total, unit=f" {unit}")
            self._phase = (unit, total)
        self._bar.update(done - self._bar.n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def _progress(progress: ProgressArg):
    """(callback for the library, function to call when the call returns).

    ``None`` (default): a bar when stderr is a terminal or the code runs in a
    Jupyter kernel, as the CLI draws one only on a terminal; ``True``: a bar;
    ``False``: nothing; a callable: called as ``progress(unit, done, total)``.
    """
    if progress is None:
        progress = "ipykernel" in sys.modules or (hasattr(sys.stderr, "isatty") and sys.stderr.isatty())
    if progress is False:
        return None, lambda: None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            bar: Any = _TextBar()
        else:
            bar = _TqdmBar(tqdm)
        return bar, bar.close
    if callable(progress):
        return progress, lambda: None
    raise TypeError(f"progress: expected None, True, False or a callable, got {type(progress).__name__}")


def _plain(obj: Any) -> Any:
    """JSON fallback for numpy scalars and arrays inside input dicts."""
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not a number, string, list or dict")


def _source(obj: Any, what: str) -> Tuple[Optional[str], Optional[str]]:
    """(path, text): a path is read by the library as the CLI reads it; a dict
    becomes JSON text, which is YAML, parsed by the same code as a file."""
    if isinstance(obj, (str, os.PathLike)):
        return os.fspath(obj), None
    if isinstance(obj, Mapping):
        return None, json.dumps(obj, default=_plain)
    raise TypeError(f"{what}: expected a path or a dict, got {type(obj).__name__}")


def _array(raw: bytes, shape: Tuple[int, ...] = (-1,)) -> np.ndarray:
    return np.frombuffer(raw, dtype="<f8").reshape(shape).astype(np.float64)


def modal(beam: PathOrDict, modes: int = 3) -> Dict[str, Any]:
    """Natural frequencies and damping ratios of a beam (``nanobeam modal --json``).

    Parameters
    ----------
    beam : dict or path
        The beam description (the BEAM.yaml structure).
    modes : int
        Number of physical modes (1 to the mesh's free DOFs).

    Returns
    -------
    dict
        ``{"modes": [{"mode", "omega_rad_s", "zeta", "pole_re_rad_s",
        "pole_im_rad_s"}, ...]}``, plus ``"overdamped_modes"`` when a physical
        mode has no oscillatory pair (mode numbers are physical).
    """
    path, text = _source(beam, "beam")
    return json.loads(_nanobeam.modal_json(path, text, int(modes)))


def frf(
    beam: PathOrDict,
    *,
    input_x_nm: float,
    output_x_nm: float,
    from_rad_s: float,
    to_rad_s: float,
    points: int,
    log: bool = False,
) -> Dict[str, np.ndarray]:
    """Receptance between a point force and a point displacement (``nanobeam frf``).

    The frequency grid is linear (or logarithmic with ``log=True``) from
    ``from_rad_s`` to ``to_rad_s`` inclusive, ``points`` frequencies.

    Returns
    -------
    dict of numpy arrays
        ``omega_rad_s``, ``h_m_per_n`` (complex receptance, m/N),
        ``magnitude_m_per_n`` and ``phase_rad``: the columns of ``--json``.
    """
    path, text = _source(beam, "beam")
    w, re, im = _nanobeam.frf_arrays(
        path,
        text,
        float(input_x_nm),
        float(output_x_nm),
        float(from_rad_s),
        float(to_rad_s),
        int(points),
        bool(log),
    )
    h = _array(re) + 1j * _array(im)
    return {
        "omega_rad_s": _array(w),
        "h_m_per_n": h,
        "magnitude_m_per_n": np.abs(h),
        "phase_rad": np.angle(h),
    }


def _idata_dict(groups) -> Dict[str, Dict[str, np.ndarray]]:
    return {
        name: {v: _array(raw, tuple(n for _, n in dims)) for v, dims, raw in variables}
        for name, _attrs, variables in groups
    }


def _idata_arviz(az, groups, attributes):
    import xarray as xr

    datasets = {}
    for name, attrs, variables in groups:
        data_vars = {}
        coords: Dict[str, np.ndarray] = {}
        for v, dims, raw in variables:
            shape = tuple(n for _, n in dims)
            data_vars[v] = ([d for d, _ in dims], _array(raw, shape))
            for d, n in dims:
                coords.setdefault(d, np.arange(n, dtype=np.int64))
        datasets[name] = xr.Dataset(data_vars, coords=coords, attrs=dict(attrs))
    idata = az.InferenceData(**datasets)
    return idata


def calibrate(
    measured: PathOrDict,
    *,
    return_summary: bool = False,
    use_arviz: Optional[bool] = None,
    progress: ProgressArg = None,
):
    """Bayesian calibration (DRAM) against measured modal data (``nanobeam calibrate``).

    The sampler settings, the seed and the parameters come from the
    measured-data structure, as for the CLI; the draws are the CLI's, bit for
    bit, at any thread count.

    Parameters
    ----------
    measured : dict or path
        The measured-data structure (MEASURED.yaml): beam, modes, optional
        held_out_modes, mode_scans, parameters and sampler.
    return_summary : bool
        Also return the summary the CLI prints with ``--json``.
    use_arviz : bool or None
        ``None`` (default): an ``arviz.InferenceData`` when ArviZ imports, else
        a dict; ``False``: always the dict; ``True``: ArviZ is required.

    Returns
    -------
    arviz.InferenceData or dict
        The groups of ``inference_data.nc`` (``posterior``, ``sample_stats``,
        ``log_likelihood``, ``observed_data``, ``prior``) with the same
        variables, dimensions, draws and attributes; without ArviZ a dict
        ``{group: {variable: ndarray}}``. With ``return_summary=True`` a
        tuple ``(idata, summary)``.
    progress : bool, callable or None
        Progress of the chains' draws (the CLI's bar). ``None`` (default): a
        bar when stderr is a terminal or in a Jupyter kernel; ``True``: a
        ``tqdm.auto`` bar when tqdm is installed, else a text line on stderr;
        ``False``: none; a callable is called as ``progress(unit, done,
        total)`` (``unit`` ``"draws"``, ``done`` non-decreasing) on the
        calling thread at most every 50 ms while the work runs. Progress never
        changes a number. An exception the callable raises cancels the run
        and is re-raised.

    Ctrl-C cancels the run and raises ``KeyboardInterrupt`` once it has
    stopped (within a few DRAM steps per chain).

    Calibration warnings (frozen chains, R-hat, ESS) are issued as Python
    warnings, and are in ``summary["warnings"]``.
    """
    path, text = _source(measured, "measured")
    callback, close = _progress(progress)
    try:
        summary_text, groups, attributes = _nanobeam.calibrate_groups(path, text, callback)
    finally:
        close()
    summary = json.loads(summary_text)
    for w in summary.get("warnings", []):
        warnings.warn(w, RuntimeWarning, stacklevel=2)
    az = None
    if use_arviz is None or use_arviz:
        try:
            import arviz as az  # noqa: F811
        except ImportError:
            if use_arviz:
                raise
            az = None
    idata = _idata_arviz(az, groups, attributes) if az is not None else _idata_dict(groups)
    return (idata, summary) if return_summary else idata


def diagnose(
    measured: PathOrDict,
    *,
    samples: Optional[int] = None,
    thorough: bool = False,
    max_causes: Optional[int] = None,
    progress: ProgressArg = None,
) -> Dict[str, Any]:
    """Model diagnosis: misfit checks, candidate causes by evidence, gain (``nanobeam diagnose --json``).

    Parameters
    ----------
    measured : dict or path
        The measured-data structure: beam, at least 3 modes, optional
        held_out_modes and mode_scans, parameters, sampler (its seed is used).
    samples : int, optional
        TMCMC samples per stage per model (default 400, or 1000 with ``thorough``).
    thorough : bool
        The library's longer default runs instead of the validated quick settings.
    max_causes : int, optional
        The most causes one model combines, 1 to 3 (default 2; ``--max-causes``).
    progress : bool, callable or None
        As for :func:`calibrate`; the unit is ``"models"``: the models whose
        evidence is done (the base, the beta baseline, every candidate).

    Ctrl-C cancels the run and raises ``KeyboardInterrupt`` once it has
    stopped (its TMCMC runs poll at every stage and sample).

    Returns
    -------
    dict
        The structure ``nanobeam diagnose --json`` prints (``misfit_detected``,
        ``cause``, ``causes``, ``explained``, ``gain``, ``candidates``,
        ``alternatives``, ``next_measurement``, ...).
    """
    path, text = _source(measured, "measured")
    callback, close = _progress(progress)
    try:
        text = _nanobeam.diagnose_json(
            path,
            text,
            None if samples is None else int(samples),
            bool(thorough),
            None if max_causes is None else int(max_causes),
            callback,
        )
    finally:
        close()
    return json.loads(text)


def _csv_text(columns: Mapping) -> str:
    names = list(columns)
    cols = [np.asarray(columns[n], dtype=np.float64).ravel() for n in names]
    if len({len(c) for c in cols}) > 1:
        raise ValueError("invalid data: allowed columns of one length")
    rows = (",".join(repr(float(x)) for x in row) for row in zip(*cols))
    return ",".join(names) + "\n" + "\n".join(rows) + "\n"


def identify(
    data: Union[str, "os.PathLike[str]", Mapping],
    beam: PathOrDict,
    *,
    modes: Optional[int] = None,
    first_mode: Optional[int] = None,
    max_order: int = 40,
    return_identification: bool = False,
):
    """Modal identification of a lab record (``nanobeam identify DATA.csv --beam BEAM.yaml``).

    Parameters
    ----------
    data : path or dict
        The record: a CSV path, or a dict ``{column name: 1-D array}`` with the
        CSV's columns (the header names the kind, e.g. ``omega_rad_s,
        h_re_m_per_n, h_im_m_per_n`` for a complex receptance).
    beam : dict or path
        The nominal beam: copied into the result, and used to number the modes.
    modes, first_mode, max_order :
        As ``--modes``, ``--first-mode``, ``--max-order``.

    Returns
    -------
    dict
        The measured-data structure (``beam`` and ``modes``), ready for
        :func:`calibrate` and :func:`diagnose`. With
        ``return_identification=True`` a tuple ``(measured, identification)``
        where ``identification`` is what ``--json`` prints.

    The warnings the CLI prints on stderr (a thermal-motion record whose fit
    scatters like far fewer Welch averages than the record's segments) are
    issued as Python ``RuntimeWarning`` with the same text (without the
    ``warning: `` prefix).
    """
    if isinstance(data, Mapping):
        data_path, data_text = None, _csv_text(data)
    elif isinstance(data, (str, os.PathLike)):
        data_path, data_text = os.fspath(data), None
    else:
        raise TypeError(f"data: expected a path or a dict of columns, got {type(data).__name__}")
    beam_path, beam_text = _source(beam, "beam")
    doc = json.loads(
        _nanobeam.identify_json(
            data_path,
            data_text,
            beam_path,
            beam_text,
            None if modes is None else int(modes),
            None if first_mode is None else int(first_mode),
            int(max_order),
        )
    )
    for w in doc.get("warnings", []):
        warnings.warn(w, RuntimeWarning, stacklevel=2)
    return (doc["measured"], doc["identification"]) if return_identification else doc["measured"]


def read_yaml(path: Union[str, "os.PathLike[str]"]) -> Dict[str, Any]:
    """A YAML file as a dict, read by the library's YAML parser (no YAML
    package needed): e.g. a BEAM.yaml or MEASURED.yaml to edit before
    calling :func:`calibrate`, or the CLI's ``identify`` output."""
    with open(os.fspath(path), encoding="utf-8") as f:
        return json.loads(_nanobeam.yaml_to_json(f.read()))
