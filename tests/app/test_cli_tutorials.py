"""``ringlab tutorials DIR``: the tutorials shipped in the package written as Jupyter notebooks."""
import nbformat
import pytest

from ringlab.cli import tutorials
from ringlab.cli.main import main
from ringlab.lessons.tutorials import TUTORIALS
from ringlab.paths import TUTORIALS_SRC_DIR


def test_writes_every_shipped_tutorial_as_a_valid_notebook(tmp_path, capsys):
    out = tmp_path / "nb"
    assert main(["tutorials", str(out)]) == 0
    written = sorted(p.stem for p in out.glob("*.ipynb"))
    assert written == sorted(TUTORIALS) == [p.stem for p in tutorials.sources()]
    assert f"jupyter lab {out}" in capsys.readouterr().out
    for stem in written:
        nb = nbformat.read(out / f"{stem}.ipynb", as_version=4)
        nbformat.validate(nb)
        code = [c for c in nb.cells if c.cell_type == "code"]
        assert code and all(not c.get("outputs") for c in code)
        src = (TUTORIALS_SRC_DIR / f"{stem}.py").read_text()
        assert code[0].source.splitlines()[0] in src  # the tutorial's own cells, not an empty notebook
        assert "jupytext" not in nb.metadata
    lecture = nbformat.read(out / "06_lecture_live_views.ipynb", as_version=4)
    assert any("HydroView()" in c.source for c in lecture.cells)


def test_keeps_existing_notebooks_unless_forced(tmp_path, capsys):
    assert main(["tutorials", str(tmp_path)]) == 0
    mark = tmp_path / "01_linear_theory.ipynb"
    mark.write_text("mine")
    assert main(["tutorials", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ringlab tutorials: error: DIR = ") and "--force" in err and err.count("\n") == 1
    assert mark.read_text() == "mine"
    assert main(["tutorials", str(tmp_path), "--force"]) == 0
    nbformat.validate(nbformat.read(mark, as_version=4))


def test_bad_folders(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(ValueError, match="is a file"):
        tutorials.write_notebooks(f)
    with pytest.raises(ValueError, match="no tutorials found"):
        tutorials.write_notebooks(tmp_path / "out", folder=tmp_path / "empty")
