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


def test_fingerprint_is_for_the_hydro_engine_only(tmp_path):
    with pytest.raises(ValueError, match="hydro"):
        warmup.main(["nbody", "--fingerprint", str(tmp_path / "f.json")])
    assert not (tmp_path / "f.json").exists()
