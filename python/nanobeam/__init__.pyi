"""Type stubs of the nanobeam package (see the module docstring of __init__.py)."""

import os
from typing import Any, Callable, Dict, Literal, Mapping, Optional, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

PathOrDict = Union[str, os.PathLike[str], Mapping[str, Any]]
# None: a bar on a terminal or in Jupyter; True: a bar; False: none;
# a callable: progress(unit, done, total) on the calling thread
ProgressArg = Union[None, bool, Callable[[str, int, int], Any]]

class NumericalError(Exception):
    """A numerical failure on valid input (the CLI's exit code 1)."""

def modal(beam: PathOrDict, modes: int = ...) -> Dict[str, Any]:
    """Natural frequencies and damping ratios (``nanobeam modal --json``)."""

def frf(
    beam: PathOrDict,
    *,
    input_x_nm: float,
    output_x_nm: float,
    from_rad_s: float,
    to_rad_s: float,
    points: int,
    log: bool = ...,
) -> Dict[str, npt.NDArray[Any]]:
    """Receptance: ``omega_rad_s``, ``h_m_per_n`` (complex), ``magnitude_m_per_n``, ``phase_rad``."""

@overload
def calibrate(
    measured: PathOrDict,
    *,
    return_summary: Literal[False] = ...,
    use_arviz: Optional[bool] = ...,
    progress: ProgressArg = ...,
) -> Any:
    """An ``arviz.InferenceData`` (a dict ``{group: {variable: ndarray}}`` without ArviZ)."""

@overload
def calibrate(
    measured: PathOrDict,
    *,
    return_summary: Literal[True],
    use_arviz: Optional[bool] = ...,
    progress: ProgressArg = ...,
) -> Tuple[Any, Dict[str, Any]]:
    """``(idata, summary)``: the summary is what ``nanobeam calibrate --json`` prints."""

def diagnose(
    measured: PathOrDict,
    *,
    samples: Optional[int] = ...,
    thorough: bool = ...,
    max_causes: Optional[int] = ...,
    progress: ProgressArg = ...,
) -> Dict[str, Any]:
    """The structure ``nanobeam diagnose --json`` prints."""

@overload
def identify(
    data: Union[str, os.PathLike[str], Mapping[str, npt.ArrayLike]],
    beam: PathOrDict,
    *,
    modes: Optional[int] = ...,
    first_mode: Optional[int] = ...,
    max_order: int = ...,
    return_identification: Literal[False] = ...,
) -> Dict[str, Any]:
    """The measured-data structure (beam and modes), ready for calibrate and diagnose."""

@overload
def identify(
    data: Union[str, os.PathLike[str], Mapping[str, npt.ArrayLike]],
    beam: PathOrDict,
    *,
    modes: Optional[int] = ...,
    first_mode: Optional[int] = ...,
    max_order: int = ...,
    return_identification: Literal[True],
) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """``(measured, identification)``: the second is what ``--json`` prints."""

def read_yaml(path: Union[str, os.PathLike[str]]) -> Dict[str, Any]:
    """A YAML file as a dict (the library's parser)."""

def campaign(
    manifest_or_folder: Union[str, os.PathLike[str]],
    beam: Optional[Union[str, os.PathLike[str]]] = ...,
    out: Optional[Union[str, os.PathLike[str]]] = ...,
    client: Any = ...,
    progress: ProgressArg = ...,
    *,
    samples: Optional[int] = ...,
    max_causes: Optional[int] = ...,
    thorough: bool = ...,
    parquet: Optional[Union[str, os.PathLike[str]]] = ...,
) -> Any:
    """Many records to one table (``nanobeam campaign``): a pandas DataFrame, one row per record."""
