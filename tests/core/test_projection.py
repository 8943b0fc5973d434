"""The projection model of a recipe's full figure on more cores (ringcore.experiments.projection)."""
import pytest

from ringcore.experiments.projection import amdahl, makespan, project, projections


def test_amdahl_through_the_measured_point():
    assert amdahl(1, 1.8) == pytest.approx(1.0)
    assert amdahl(2, 1.8) == pytest.approx(1.8)
    assert amdahl(10**6, 1.8) == pytest.approx(1 / (2 / 1.8 - 1), rel=1e-4)  # the serial fraction's limit
    assert amdahl(64, 2.0) == pytest.approx(64.0)
    with pytest.raises(ValueError, match="thread_factor"):
        amdahl(2, 2.5)


def test_makespan_longest_first():
    assert makespan([2, 3, 3, 4], 2) == 6  # longest first: {4, 2}, {3, 3}; in the given order it would be 7
    assert makespan([5, 1], 8) == 5


def test_project_runs_then_threads():
    ten = [100.0] * 10
    # as many cores as runs (one node): one thread each, slowed by the measured sharing factor
    p = project(ten, 1, 10, worker_factor=1.8, thread_factor=1.8)
    assert p["threads"] == 1 and p["wall_s"] == pytest.approx(100.0 / 0.9)
    # fewer cores than runs: rounds of runs
    assert project(ten, 1, 2, 2.0, 2.0)["wall_s"] == pytest.approx(500.0)
    # more cores than runs: the rest go to threads, as many as give each run its own cores at once
    p = project(ten, 1, 64, 1.8, 1.8)
    assert p["threads"] == 6 and p["wall_s"] == pytest.approx(100.0 / (amdahl(6, 1.8) * 0.9))
    # a node per run: no sharing slow-down, threads as the node allows
    p = project(ten, 10, 32, worker_factor=1.0, thread_factor=2.0)
    assert p["threads"] == 32 and p["wall_s"] == pytest.approx(100.0 / 32)
    rows = projections(ten, 2.0, 2.0, [("2 cores", 1, 2), ("x", 10, 32)])
    assert [r["cores"] for r in rows] == [2, 320] and rows[0]["wall_h"] == pytest.approx(500.0 / 3600)
