"""The identify warning on a thermal-motion record, Python against the CLI.

Record: the committed LAMMPS record ``data/md/cc11.langevin.csv.gz`` (made by
LAMMPS, ``data/md/README.md``; the 11.4 nm clamped-clamped (5,5) tube) with its
nominal beam ``data/md/tube-cc11.yaml``, untouched but for ``first_mode=1``
(without it the numbering is refused as ambiguous, tests/identify_md.md).
Its fit scatters like 0.65 Welch averages where each column gives 2 segments
(tests/identify_md.md), below the warning's level of half the segments: the
CLI prints one ``warning:`` line. The reference is that line from the CLI
binary (a separate program, its stderr); the Python function must issue the
same text as a ``RuntimeWarning`` and return the same measured data.
"""

from __future__ import annotations

import gzip
import json
import warnings

import nanobeam
from test_cli_parity import ROOT, cli

RECORD = ROOT / "data" / "md" / "cc11.langevin.csv.gz"
BEAM = ROOT / "data" / "md" / "tube-cc11.yaml"


def test_nu_warning_of_a_thermal_record_is_the_cli_line(tmp_path):
    csv_path = tmp_path / "cc11.csv"
    csv_path.write_bytes(gzip.decompress(RECORD.read_bytes()))
    out = cli("identify", str(csv_path), "--beam", str(BEAM), "--first-mode", "1", "--json")
    assert out.returncode == 0, out.stderr
    lines = [line for line in out.stderr.splitlines() if line.startswith("warning: ")]
    assert len(lines) == 1, out.stderr
    expected = lines[0][len("warning: "):]
    assert "Welch averages" in expected
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        measured, ident = nanobeam.identify(str(csv_path), str(BEAM), first_mode=1, return_identification=True)
    texts = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert texts == [expected]
    assert ident == json.loads(out.stdout)


def test_a_record_the_fit_explains_gives_no_warning(tmp_path):
    # a noise-free complex sweep of the hand-written beam of test_cli_parity
    # (not a thermal record): the CLI prints no warning, Python issues none
    from test_cli_parity import VISCO, write

    beam_path = write(tmp_path, "beam.yaml", VISCO)
    sweep = cli(
        "frf", beam_path, "--input-x-nm=2", "--output-x-nm=5.5", "--from-rad-s=2e11",
        "--to-rad-s=6e12", "--points=1200", "--log", "--csv",
    )
    assert sweep.returncode == 0, sweep.stderr
    csv_path = write(tmp_path, "sweep.csv", sweep.stdout)
    out = cli("identify", csv_path, "--beam", beam_path, "--modes", "3")
    assert out.returncode == 0 and "warning:" not in out.stderr, out.stderr
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        nanobeam.identify(csv_path, VISCO, modes=3)
    assert not [w for w in caught if issubclass(w.category, RuntimeWarning)]
