"""Recipe registry and the ``ringcore reproduce`` command."""
import pytest

from ringcore.cli.main import main
from ringcore.experiments import get_recipe, run_recipe
from ringcore.experiments.registry import load_all
from ringcore.io import read_run
from ringcore.paperlabels import raw_labels
from ringcore.paperrefs import ref


def test_list_shows_every_recipe_with_figure_and_costs(capsys):
    assert main(["reproduce", "--list"]) == 0
    out = capsys.readouterr().out
    for name, r in load_all().items():
        line = next(l for l in out.splitlines() if l.startswith(name + " "))
        assert ref(r.figure) in line  # the published number a reader can look up ...
    assert not raw_labels(out) and "fig:" not in out and "sec:" not in out  # ... and no LaTeX label


@pytest.mark.parametrize("name", ["omega", "vgph"])
def test_linear_recipes_write_png_and_data(name, tmp_path):
    res = run_recipe(name, "quick", tmp_path)
    assert res.png.stat().st_size > 20_000
    ds = read_run(res.data, kind="linear")
    assert ds.attrs["caption"] == res.caption
    assert "growth_rate_nonisothermal" in ds and ds.wavelength.attrs["units"] == "m"


def test_unknown_recipe_and_mode():
    with pytest.raises(ValueError, match="recipe = 'nope'"):
        get_recipe("nope")
    with pytest.raises(ValueError, match="mode"):
        run_recipe("omega", "slow")
    assert main(["reproduce", "nope"]) == 2
