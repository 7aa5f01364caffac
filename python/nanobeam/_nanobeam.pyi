"""The compiled half (PyO3); use the functions of ``nanobeam`` instead."""

from typing import Any, Callable, List, Optional, Tuple

ProgressCallback = Optional[Callable[[str, int, int], Any]]

__version__: str

class NumericalError(Exception): ...

def modal_json(beam_path: Optional[str], beam_text: Optional[str], modes: int) -> str: ...
def frf_arrays(
    beam_path: Optional[str],
    beam_text: Optional[str],
    input_x_nm: float,
    output_x_nm: float,
    from_rad_s: float,
    to_rad_s: float,
    points: int,
    log: bool,
) -> Tuple[bytes, bytes, bytes]: ...
def calibrate_groups(
    measured_path: Optional[str], measured_text: Optional[str], progress: ProgressCallback
) -> Tuple[
    str,
    List[Tuple[str, List[Tuple[str, str]], List[Tuple[str, List[Tuple[str, int]], bytes]]]],
    List[Tuple[str, str]],
]: ...
def diagnose_json(
    measured_path: Optional[str],
    measured_text: Optional[str],
    samples: Optional[int],
    thorough: bool,
    max_causes: Optional[int],
    progress: ProgressCallback,
) -> str: ...
def identify_json(
    data_path: Optional[str],
    data_text: Optional[str],
    beam_path: Optional[str],
    beam_text: Optional[str],
    modes: Optional[int],
    first_mode: Optional[int],
    max_order: int,
) -> str: ...
def yaml_to_json(text: str) -> str: ...
def campaign_plan(
    source: str,
    beam: Optional[str],
    samples: Optional[int],
    max_causes: Optional[int],
    thorough: bool,
    out: Optional[str],
) -> str: ...
def campaign_record(task_json: str, progress: ProgressCallback = ...) -> str: ...
def campaign_csv(rows_json: str) -> str: ...
def campaign_write(out: str, rows_json: str) -> None: ...
