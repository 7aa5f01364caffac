"""``nanobeam.campaign``: many records to one table, locally or on a Dask cluster.

The plan (manifest or folder, the rows of an earlier table that are still
current), each record's work and the table's CSV are the CLI's own
(``nanobeam campaign``, docs/campaign.md), through ``_nanobeam.campaign_plan``,
``campaign_record`` and ``campaign_csv``; this module only distributes the
records and builds the DataFrame. pandas is needed, dask only with ``client=``
(``pip install ./python[campaign]``).
"""

from __future__ import annotations

import io
import json
import os
import sys
import uuid
from typing import Any, Callable, Dict, List, Optional, Union

from . import _nanobeam

PathLike = Union[str, "os.PathLike[str]"]

#: Numeric columns of the table (the rest are text; an empty cell is NaN here, "" in text columns).
NUMERIC_COLUMNS = (
    "row",
    "log_evidence",
    "log_bayes_factor",
    "e0a_mean_nm",
    "e0a_ci95_lo_nm",
    "e0a_ci95_hi_nm",
    "forward_solves",
    "wall_s",
)


def _run_record(task_json: str) -> str:
    """One record on whichever process runs it (a Dask worker, or here)."""
    from nanobeam import _nanobeam as ext

    return ext.campaign_record(task_json, None)


class _RecordsBar:
    """``done/total records`` and the record last finished: a tqdm bar (a widget
    in Jupyter) when tqdm is installed, else one text line on stderr."""

    def __init__(self, total: int, done: int) -> None:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            self._bar: Any = None
        else:
            self._bar = tqdm(total=total, initial=done, unit=" records")
        self._total = total
        self._done = done

    def __call__(self, done: int, record: str) -> None:
        if self._bar is not None:
            self._bar.set_postfix_str(record, refresh=False)
            self._bar.update(done - self._bar.n)
        else:
            sys.stderr.write(f"\r{done}/{self._total} records {record}\x1b[K")
            sys.stderr.flush()
        self._done = done

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
        else:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _progress(progress: Any, total: int, done: int):
    if progress is None:
        progress = "ipykernel" in sys.modules or (hasattr(sys.stderr, "isatty") and sys.stderr.isatty())
    if progress is False:
        return (lambda done, record: None), (lambda: None)
    if progress is True:
        bar = _RecordsBar(total, done)
        return bar, bar.close
    if callable(progress):
        return (lambda d, record: progress("records", d, total)), (lambda: None)
    raise TypeError(f"progress: expected None, True, False or a callable, got {type(progress).__name__}")


def _frame(rows: List[Dict[str, Any]]):
    """The table as the CSV reads back, numeric columns as numbers, and the
    ``posterior`` JSON cell expanded into ``mean:NAME``, ``ci95_lo:NAME``,
    ``ci95_hi:NAME`` columns (names sorted)."""
    import pandas as pd

    text = _nanobeam.campaign_csv(json.dumps(rows))
    df = pd.read_csv(io.StringIO(text), dtype=str, keep_default_na=False)
    for c in NUMERIC_COLUMNS:
        df[c] = pd.to_numeric(df[c], errors="coerce")
    df["row"] = df["row"].astype("int64")
    posteriors = [json.loads(p) if p else {} for p in df["posterior"]]
    names = sorted({name for p in posteriors for name in p})
    for name in names:
        nan = float("nan")
        df[f"mean:{name}"] = [p[name]["mean"] if name in p else nan for p in posteriors]
        df[f"ci95_lo:{name}"] = [p[name]["ci95"][0] if name in p else nan for p in posteriors]
        df[f"ci95_hi:{name}"] = [p[name]["ci95"][1] if name in p else nan for p in posteriors]
    return df


def campaign(
    manifest_or_folder: PathLike,
    beam: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    client: Any = None,
    progress: Union[None, bool, Callable[[str, int, int], Any]] = None,
    *,
    samples: Optional[int] = None,
    max_causes: Optional[int] = None,
    thorough: bool = False,
    parquet: Optional[PathLike] = None,
):
    """Many records to one table (``nanobeam campaign``; docs/campaign.md).

    Parameters
    ----------
    manifest_or_folder : path
        A manifest CSV (``record`` and optional ``beam``, ``support``,
        ``kind``, ``action``, ``first_mode``, ``modes``, ``max_order``,
        ``samples``, ``max_causes``, ``seed`` columns; paths relative to its
        folder) or a folder whose ``.csv``, ``.csv.gz``, ``.yaml`` and
        ``.yml`` files are the records.
    beam : path, optional
        The beam file of every lab record whose row names none.
    out : path, optional
        The table (CSV), rewritten atomically after every record; an existing
        table is resumed (the records whose bytes, beam and options match an
        ``ok`` row are not run again). The same file the CLI writes.
    client : dask.distributed.Client, optional
        Runs the records on the cluster's workers (each needs this package
        and the record files at the same paths). Without one the records run
        here one after another, each diagnosis parallel on all local cores.
    progress : bool, callable or None
        Records done / total and the current record: ``None`` (default) a bar
        on a terminal or in Jupyter, ``True`` a bar, ``False`` none, a
        callable is called as ``progress("records", done, total)``.
    samples, max_causes, thorough
        diagnose's ``--samples``, ``--max-causes``, ``--thorough`` for every record.
    parquet : path, optional
        Also write the DataFrame as Parquet (needs pyarrow).

    Returns
    -------
    pandas.DataFrame
        One row per record in manifest order: the table's columns, numbers as
        floats, and the selected model's posterior expanded into
        ``mean:NAME``, ``ci95_lo:NAME`` and ``ci95_hi:NAME`` columns. Every
        column but ``wall_s`` is the same at any worker count.
    """
    try:
        import pandas  # noqa: F401
    except ImportError as e:
        raise ImportError("nanobeam.campaign needs pandas: pip install ./python[campaign]") from e
    out_s = None if out is None else os.fspath(out)
    plan = json.loads(
        _nanobeam.campaign_plan(
            os.fspath(manifest_or_folder),
            None if beam is None else os.fspath(beam),
            None if samples is None else int(samples),
            None if max_causes is None else int(max_causes),
            bool(thorough),
            out_s,
        )
    )
    rows: List[Dict[str, Any]] = list(plan["kept"])
    tasks = plan["tasks"]
    total = plan["total"]
    update, close = _progress(progress, total, len(rows))

    def done(row: Dict[str, Any]) -> None:
        rows.append(row)
        if out_s is not None:
            _nanobeam.campaign_write(out_s, json.dumps(rows))
        update(len(rows), row["record"])

    if out_s is not None:
        _nanobeam.campaign_write(out_s, json.dumps(rows))
    try:
        if client is None:
            for task in tasks:
                done(json.loads(_run_record(json.dumps(task))))
        else:
            from dask.distributed import as_completed

            batch = uuid.uuid4().hex
            futures = [
                client.submit(_run_record, json.dumps(task), key=f"nanobeam-campaign-{batch}-{task['row']}")
                for task in tasks
            ]
            for future in as_completed(futures):
                done(json.loads(future.result()))
    finally:
        close()
    df = _frame(rows)
    if parquet is not None:
        df.to_parquet(os.fspath(parquet))
    return df
