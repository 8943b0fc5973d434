"""Provenance: every new run file and sweep file records the version and the git commit of the code that wrote
it; ringcore.cite() gives the paper and the software as BibTeX; LICENSE and CITATION.cff are present."""
from __future__ import annotations

import argparse
import re
import subprocess
from pathlib import Path

import pytest
import xarray as xr

import ringcore
from ringcore import params, provenance
from ringcore.hydro import Hydro1D, HydroOptions

ROOT = Path(__file__).resolve().parents[2]


def _git_head():
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True, text=True)
    except OSError:
        return None
    return out.stdout.strip() if out.returncode == 0 else None


def test_version_is_derived_not_the_old_constant():
    v = ringcore.__version__
    assert re.fullmatch(r"\d+\.\d+(\.\d+)?([.+-][0-9A-Za-z.+-]+)?", v), v
    if (ROOT / "ringcore" / "_version.py").is_file():  # installed with setuptools-scm: the version comes from it
        from ringcore._version import version

        assert v == version


def test_new_run_file_records_version_and_commit(tmp_path):
    p = params.get("tau15", sigma0=400)
    eng = Hydro1D(p, HydroOptions(L_x=200.0, h=5.0), initial="noise", seed=1)
    eng.advance(orbits=0.05)
    path = eng.save(tmp_path / "run.nc")
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["ringcore_version"] == ringcore.__version__
        commit = ds.attrs["ringcore_commit"]
    head = _git_head()
    if head is None:  # not a checkout: the commit recorded at build time, or "unknown" without one
        assert commit
    else:
        assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?", commit) and commit.startswith(head)
    assert ringcore.engine.load(path).orbits == pytest.approx(eng.orbits)  # the new attributes read back


def test_sweep_file_attributes_record_version_and_commit():
    from ringcore.cli.sweep_cmd import provenance as sweep_provenance

    args = argparse.Namespace(engine="hydro", set="tau15", isothermal=False,
                              _argv=["sweep", "--engine", "hydro", "--sigma0", "100"])
    a = sweep_provenance(args)
    assert a["ringcore_version"] == ringcore.__version__ and a["ringcore_commit"] == provenance.commit()


def test_cite_gives_paper_and_software_bibtex(capsys):
    text = ringcore.cite()
    assert capsys.readouterr().out == text
    assert "@article{Lehmann2017" in text and "{851}" in text and "{125}" in text and "1804.07968" in text
    assert "@software{ringlab" in text and ringcore.__version__ in text and provenance.commit() in text
    assert text.count("{") == text.count("}")  # balanced BibTeX
    assert ringcore.cite(show=False) == text and capsys.readouterr().out == ""


def test_license_and_citation_metadata():
    lic = (ROOT / "LICENSE").read_text()
    assert "BSD 3-Clause" in lic and "Neither the name of the copyright holder" in lic
    cff = (ROOT / "CITATION.cff").read_text()
    assert "cff-version: 1.2.0" in cff and "preferred-citation:" in cff and "volume: 851" in cff
    assert "license: BSD-3-Clause" in cff


def test_compact_long_run_file_records_its_code_and_its_source(tmp_path):
    from ringcore.experiments.longruns import compact

    p = params.get("tau15", sigma0=0.0, isothermal=True)
    sim = Hydro1D(p, HydroOptions(L_x=400.0, h=2.5, timestep="cfl", samples_per_orbit=10),
                  initial="mode", wavelength=100.0, amplitude=1e-3)
    sim.run(orbits=3)
    src = sim.save(tmp_path / "iso_tau15_mode100.nc")
    c = compact(src, rows=4, cols=20)
    assert c.attrs["ringcore_version"] == ringcore.__version__ and c.attrs["ringcore_commit"] == provenance.commit()
    assert c.attrs["source_ringcore_commit"] == provenance.commit()  # the run file's own record, carried over
