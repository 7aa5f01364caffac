"""The identify warning on a thermal-motion record, Python against the CLI.

Record (generated here, numpy ``default_rng(5)``): one ``thermal_a_m``
column of 2^15 samples at 20 fs, an AR(2) line (poles 0.99·e^{±0.3i} per
sample) plus white noise cut by a brick wall to 0.9–1.2 rad/sample at three
times the line's sd. A rational fit cannot follow the brick wall's edges, so
the fit's residuals scatter like far fewer Welch averages than the record's
segments (measured: ν̂ = 0.17 against 31), below the warning's level of half
the segments: the CLI prints one ``warning:`` line. The reference is that
line from the CLI binary (a separate program, its stderr); the Python
function must issue the same text as a ``RuntimeWarning`` and return the
same identification. The beam only numbers the modes: the line, at 0.3 rad per sample
(1.5e13 rad/s), is mode 8 of the cc11 tube over the whole prior (``first_mode=8``; a stated first
mode the prior cannot fit is refused).
"""

from __future__ import annotations

import json
import warnings

import numpy as np

import nanobeam
from test_cli_parity import ROOT, cli

BEAM = ROOT / "data" / "md" / "tube-cc11.yaml"


def brick_record() -> str:
    rng = np.random.default_rng(5)
    n, burn, dt = 1 << 15, 5000, 2e-14
    p1, p2 = 2 * 0.99 * np.cos(0.3), -(0.99**2)
    e = rng.standard_normal(n + burn) * 1e-12
    x = np.zeros(n + burn)
    for k in range(2, n + burn):
        x[k] = p1 * x[k - 1] + p2 * x[k - 2] + e[k]
    line = x[burn:]
    w = np.fft.rfft(rng.standard_normal(n))
    theta = np.linspace(0, np.pi, len(w))
    w[(theta < 0.9) | (theta > 1.2)] = 0
    y = line + np.fft.irfft(w, n) * np.std(line) * 3
    rows = (f"{k * dt:.9e},{v:.9e}" for k, v in enumerate(y))
    return "time_s,thermal_a_m\n" + "\n".join(rows) + "\n"


def test_nu_warning_of_a_thermal_record_is_the_cli_line(tmp_path):
    csv_path = tmp_path / "brick.csv"
    csv_path.write_text(brick_record())
    out = cli("identify", str(csv_path), "--beam", str(BEAM), "--first-mode", "8", "--json")
    assert out.returncode == 0, out.stderr
    lines = [line for line in out.stderr.splitlines() if line.startswith("warning: ")]
    assert len(lines) == 1, out.stderr
    expected = lines[0][len("warning: "):]
    assert "Welch averages" in expected
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        measured, ident = nanobeam.identify(str(csv_path), str(BEAM), first_mode=8, return_identification=True)
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
