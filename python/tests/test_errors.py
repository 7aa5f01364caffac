"""Error mapping and interruption: ``ValueError`` carries the one line the CLI
prints on stderr with exit code 2, ``nanobeam.NumericalError`` the line of exit
code 1; a real SIGINT from outside interrupts a long call (test_control.py
checks the cancellation itself). The reference lines come from the CLI
binary (see test_cli_parity.py) on the same files; the inputs are hand-written.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

import nanobeam
from test_cli_parity import NOMINAL, SAMPLER, VISCO, cli, hidden_mass_data, write


def cli_error(*args: str, code: int) -> str:
    out = cli(*args)
    assert out.returncode == code, (out.returncode, out.stderr)
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    return lines[0]


def test_bad_beam_field_is_a_value_error_with_the_cli_line(tmp_path):
    bad = dict(NOMINAL, length_nm=-1.0)
    path = write(tmp_path, "beam.yaml", bad)
    line = cli_error("modal", path, "--json", code=2)
    assert "length_nm" in line
    for given in (bad, path):
        with pytest.raises(ValueError) as e:
            nanobeam.modal(given)
        assert str(e.value) == line


def test_unknown_variant_and_unreadable_file(tmp_path):
    bad = dict(NOMINAL, support="hinged")
    path = write(tmp_path, "beam.yaml", bad)
    line = cli_error("modal", path, code=2)
    with pytest.raises(ValueError) as e:
        nanobeam.modal(path)
    assert str(e.value) == line
    missing = str(tmp_path / "absent.yaml")
    line = cli_error("modal", missing, code=2)
    with pytest.raises(ValueError) as e:
        nanobeam.modal(missing)
    assert str(e.value) == line


def test_flag_errors(tmp_path):
    path = write(tmp_path, "beam.yaml", VISCO)
    line = cli_error("modal", path, "--modes", "0", code=2)
    with pytest.raises(ValueError, match="^invalid --modes") as e:
        nanobeam.modal(VISCO, 0)
    assert str(e.value) == line
    grid = {"input_x_nm": 2.0, "output_x_nm": 5.0, "from_rad_s": 1e10, "to_rad_s": 1e12, "points": 10}
    # below --from-rad-s; too few points; not a number
    for key, value in (("to_rad_s", 1e9), ("points", 1), ("from_rad_s", float("nan"))):
        args = dict(grid, **{key: value})
        line = cli_error("frf", path, *[f"--{k.replace('_', '-')}={v}" for k, v in args.items()], code=2)
        assert key.replace("_", "-") in line
        with pytest.raises(ValueError) as e:
            nanobeam.frf(VISCO, **args)
        assert str(e.value) == line


def test_sampler_and_diagnose_settings_errors(tmp_path):
    data = hidden_mass_data(modes=3, elements=8)
    data["sampler"]["draws_per_chain"] = 120  # < burn_in + 40
    path = write(tmp_path, "m.yaml", data)
    line = cli_error("calibrate", path, code=2)
    assert "sampler.draws_per_chain" in line
    with pytest.raises(ValueError) as e:
        nanobeam.calibrate(data)
    assert str(e.value) == line
    line = cli_error("diagnose", path, "--samples", "3", code=2)
    with pytest.raises(ValueError) as e:
        nanobeam.diagnose(path, samples=3)
    assert str(e.value) == line
    line = cli_error("diagnose", path, "--max-causes", "4", code=2)
    assert "--max-causes" in line
    with pytest.raises(ValueError) as e:
        nanobeam.diagnose(path, max_causes=4)
    assert str(e.value) == line


def test_numerical_failure_is_numerical_error(tmp_path):
    # every prior draw of the viscous damping lies above the model's bound:
    # no valid state, exit code 1
    data = hidden_mass_data(modes=3, elements=8)
    data["parameters"] = {
        "viscous_damping_n_s_m2": {"prior": {"dist": "uniform", "lower": 1e3, "upper": 2e3}, "proposal_sd": 1.0}
    }
    path = write(tmp_path, "m.yaml", data)
    line = cli_error("calibrate", path, code=1)
    with pytest.raises(nanobeam.NumericalError) as e:
        nanobeam.calibrate(data)
    assert str(e.value) == line
    assert not issubclass(nanobeam.NumericalError, ValueError)


def test_ctrl_c_interrupts_a_long_calibration(tmp_path):
    data = hidden_mass_data(modes=4, elements=20)
    # about a minute of sampling on one thread: far longer than the test waits
    # a known axial tension (a beam field, not sampled) takes every solve off the
    # interpolated Euler-Bernoulli path (about 0.7 us a solve on an idle machine,
    # where 2 x 200 000 plain steps took 0.3 s): 2 x 1 000 000 steps at ~16 us
    # are about half a minute on an idle machine, far longer than the test waits
    data["beam"]["axial_force_n"] = 1e-10
    data["sampler"] = dict(SAMPLER, draws_per_chain=1_000_000, chains=2)
    path = write(tmp_path, "m.yaml", data)
    code = (
        "import signal, sys, nanobeam\n"
        # as at a terminal, whatever SIGINT disposition the test runner inherited
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "print('started', flush=True)\n"
        "try:\n"
        "    nanobeam.calibrate(sys.argv[1])\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
        "    sys.exit(0)\n"
        "sys.exit(3)\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", code, path], stdout=subprocess.PIPE, text=True, env=dict(os.environ, RAYON_NUM_THREADS="1")
    )
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.5)
    assert p.poll() is None, "the calibration ended before the interrupt"
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    line = p.stdout.readline().strip()
    waited = time.monotonic() - sent
    assert line == "interrupted"
    # the call returns within the poll period (50 ms) plus one DRAM step and
    # process scheduling; 5 s leaves room for a loaded 2-core CI machine
    # (test_control.py measures the latency inside the process)
    assert waited < 5.0
    # the computation was cancelled, not left running: the process exits at once
    assert p.wait(timeout=30) == 0
