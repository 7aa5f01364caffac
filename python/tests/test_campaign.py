"""nanobeam.campaign: serial, on a Dask LocalCluster of 2 workers, and the CLI give one table.

Records (small: three modes on an 8-element mesh, ``samples=50``,
``max_causes=1``, about 2 s each in the dev build):

* ``m3.yaml``: the hand-written three-mode measured-data file of
  ``tests/campaign_cli.rs`` (the modes of ``tests/diagnose_cli.rs``);
* ``m3b.yaml``: the same with other damping ratios;
* ``sweep.csv``: ``nanobeam.frf`` of ``VISCO`` (``test_cli_parity``, 8 elements) with 2 %
  of |H| of Gaussian noise on each part (numpy ``default_rng(68)``),
  identified (``modes = 3``) against that beam;
* ``missing.yaml``: no such file (an error row).

Every column but ``wall_s`` must be equal between the serial run, the
cluster's (records finish in any order on two workers) and the CLI's table.
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import nanobeam
from test_cli_parity import VISCO, cli, write

pd = pytest.importorskip("pandas")
distributed = pytest.importorskip("dask.distributed")

M3 = """beam: { length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, support: simply-supported, elements: 8 }
modes:
  - { mode: 1, omega_rad_s: 8.3e11, omega_sd_rad_s: 2.5e9, zeta: 0.07, zeta_sd: 0.002 }
  - { mode: 2, omega_rad_s: 2.9e12, omega_sd_rad_s: 9e9, zeta: 0.05, zeta_sd: 0.0015 }
  - { mode: 3, omega_rad_s: 5.3e12, omega_sd_rad_s: 1.6e10, zeta: 0.03, zeta_sd: 0.001 }
"""


def records(tmp_path):
    write(tmp_path, "m3.yaml", M3)
    write(tmp_path, "m3b.yaml", M3.replace("zeta: 0.05,", "zeta: 0.045,"))
    beam8 = dict(VISCO, elements=8)
    beam = write(tmp_path, "beam.yaml", json.dumps(beam8))  # JSON is YAML
    r = nanobeam.frf(beam8, input_x_nm=2, output_x_nm=5.5, from_rad_s=2e11, to_rad_s=6e12, points=1200, log=True)
    h = r["h_m_per_n"]
    rng = np.random.default_rng(68)
    noisy = h + 0.02 * np.abs(h) * (rng.standard_normal(h.size) + 1j * rng.standard_normal(h.size))
    lines = ["omega_rad_s,h_re_m_per_n,h_im_m_per_n"]
    lines += [f"{w:.17e},{z.real:.17e},{z.imag:.17e}" for w, z in zip(r["omega_rad_s"], noisy)]
    write(tmp_path, "sweep.csv", "\n".join(lines) + "\n")
    manifest = "record,beam,modes\nm3.yaml,,\nsweep.csv,beam.yaml,3\nmissing.yaml,,\nm3b.yaml,,\n"
    return write(tmp_path, "manifest.csv", manifest), beam


def cells(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["wall_s"] = ""
    return rows


def test_serial_cluster_and_cli_give_the_same_table(tmp_path):
    manifest, _ = records(tmp_path)
    opts = dict(samples=50, max_causes=1, progress=False)
    serial = nanobeam.campaign(manifest, out=tmp_path / "serial.csv", **opts)
    assert list(serial["status"]) == ["ok", "ok", "error", "ok"]
    assert list(serial["row"]) == [1, 2, 3, 4]
    assert "missing.yaml" in serial["error"][2]
    assert serial["e0a_mean_nm"].notna().sum() == 3
    assert "mean:nonlocal_e0a_nm" in serial.columns
    assert (serial["mean:nonlocal_e0a_nm"].dropna() == serial["e0a_mean_nm"].dropna()).all()

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as lc:
        with distributed.Client(lc) as client:
            on_cluster = nanobeam.campaign(manifest, out=tmp_path / "cluster.csv", client=client, **opts)
    pd.testing.assert_frame_equal(serial.drop(columns="wall_s"), on_cluster.drop(columns="wall_s"))
    assert cells(tmp_path / "serial.csv") == cells(tmp_path / "cluster.csv")

    out = cli("campaign", manifest, "--out", str(tmp_path / "cli.csv"), "--samples", "50", "--max-causes", "1")
    assert out.returncode == 0, out.stderr
    assert cells(tmp_path / "cli.csv") == cells(tmp_path / "serial.csv")

    # resumed: nothing left to run but the failed record
    seen = []
    again = nanobeam.campaign(
        manifest, out=tmp_path / "serial.csv", progress=lambda u, d, t: seen.append((u, d, t)), samples=50, max_causes=1
    )
    assert seen == [("records", 4, 4)]
    pd.testing.assert_frame_equal(serial.drop(columns="wall_s"), again.drop(columns="wall_s"))


def test_a_malformed_manifest_raises_the_cli_line(tmp_path):
    manifest = write(tmp_path, "manifest.csv", "record,colour\na.yaml,red\n")
    out = cli("campaign", manifest)
    assert out.returncode == 2
    with pytest.raises(ValueError) as e:
        nanobeam.campaign(manifest, progress=False)
    assert str(e.value) == out.stderr.strip()
