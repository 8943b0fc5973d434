"""ringcore.warmup: the kernels compiled (or loaded) ahead of the processes that need them."""
import pytest

from ringcore import warmup


def test_unknown_engine_is_named():
    with pytest.raises(ValueError, match=r"engine = 'fluid' is not valid: choose one of hydro, nbody"):
        warmup.compile_kernels("fluid")


def test_parallel_warm_up_reports_each_engine():
    """Each engine in its own process; exit status 0 and the seconds until it ended (the kernels are cached
    by then: the suite's controller compiled them before the workers started)."""
    out = warmup.compile_in_parallel(("hydro", "nbody"))
    assert set(out) == {"hydro", "nbody"}
    for rc, seconds in out.values():
        assert rc == 0 and seconds > 0.0


def test_a_failing_engine_is_reported_not_raised():
    rc, seconds = warmup.compile_in_parallel(("fluid",))["fluid"]
    assert rc != 0 and seconds > 0.0


def test_fingerprint_is_for_the_hydro_engine_only(tmp_path, capsys):
    assert warmup.main(["nbody", "--fingerprint", str(tmp_path / "f.json")]) == 2
    err = capsys.readouterr().err
    assert err == "ringcore.warmup: error: --fingerprint is for the hydro engine, not 'nbody'\n"
    assert not (tmp_path / "f.json").exists()


def test_bad_engine_and_unwritable_fingerprint_are_one_line(tmp_path, capsys):
    assert warmup.main(["hydro", "fluid"]) == 2
    assert capsys.readouterr().err.strip() == ("ringcore.warmup: error: engine = 'fluid' is not valid: choose one "
                                               "of hydro, nbody")
    assert warmup.main(["hydro", "--fingerprint", str(tmp_path / "missing" / "f.json")]) == 1
    err = capsys.readouterr().err
    assert err.startswith("ringcore.warmup: cannot write ") and "f.json" in err and len(err.splitlines()) == 1
