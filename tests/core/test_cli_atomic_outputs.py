"""Outputs are written atomically and never replaced unasked: figures, recipe data,
run files and the sweep summary all go through :mod:`ringcore.io.atomic`."""
from __future__ import annotations

import matplotlib.figure
import pytest

from ringcore.cli.main import main
from ringcore.io import OutputExists, atomic_output, output_policy, save_figure, write_run
from ringcore.figures._mpl import subplots


def _fig():
    fig, ax = subplots(figsize=(3, 2))
    ax.plot([0, 1], [0, 1])
    return fig


def test_interrupted_write_leaves_no_partial_file_and_keeps_the_old_one(tmp_path):
    f = tmp_path / "a.png"
    f.write_bytes(b"old")
    with pytest.raises(KeyboardInterrupt):
        with atomic_output(f, overwrite=True) as tmp:
            tmp.write_bytes(b"half a fi")
            raise KeyboardInterrupt("SIGTERM")
    assert f.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["a.png"]
    g = tmp_path / "new.png"
    with pytest.raises(RuntimeError):
        with atomic_output(g) as tmp:
            tmp.write_bytes(b"x")
            raise RuntimeError("disk full")
    assert not g.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["a.png"]


def test_no_clobber_refuses_before_and_at_the_move(tmp_path):
    f = tmp_path / "fig.png"
    f.write_bytes(b"precious")
    with pytest.raises(OutputExists, match="fig.png: exists: refusing.*--overwrite"):
        save_figure(_fig(), f, overwrite=False)
    assert f.read_bytes() == b"precious"
    g = tmp_path / "late.png"  # appears while the new one is being written: still kept
    with pytest.raises(OutputExists):
        with atomic_output(g, overwrite=False) as tmp:
            tmp.write_bytes(b"new")
            g.write_bytes(b"someone else's")
    assert g.read_bytes() == b"someone else's" and not list(tmp_path.glob(".late.png.*.part"))
    save_figure(_fig(), f, overwrite=True)
    assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with output_policy(False):  # overwrite=None follows the policy
        with pytest.raises(OutputExists):
            save_figure(_fig(), f)
        import xarray as xr
        with pytest.raises(OutputExists):
            write_run(xr.Dataset({"a": ("x", [1.0])}), f, kind="recipe")
    assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_reproduce_refuses_an_existing_png_without_overwrite(tmp_path, capsys):
    (tmp_path / "omega.png").write_bytes(b"my figure")
    assert main(["reproduce", "omega", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "--overwrite" in err and "omega.png" in err and "Traceback" not in err and len(err.splitlines()) == 1
    assert (tmp_path / "omega.png").read_bytes() == b"my figure" and not (tmp_path / "omega.nc").exists()


def test_reproduce_interrupted_mid_write_leaves_no_partial_file(tmp_path, capsys, monkeypatch):
    real = matplotlib.figure.Figure.savefig

    def half_then_stop(self, fname, *a, **k):
        real(self, fname, *a, **k)
        with open(fname, "r+b") as fh:  # a half-written file, then SIGINT
            fh.truncate(100)
        raise KeyboardInterrupt("SIGINT")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", half_then_stop)
    assert main(["reproduce", "omega", "--out", str(tmp_path)]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # neither a partial omega.png nor a .part file
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", real)
    (tmp_path / "omega.png").write_bytes(b"old")
    assert main(["reproduce", "omega", "--out", str(tmp_path), "--overwrite"]) == 0
    assert (tmp_path / "omega.png").read_bytes()[:4] == b"\x89PNG" and (tmp_path / "omega.nc").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["omega.nc", "omega.png"]
