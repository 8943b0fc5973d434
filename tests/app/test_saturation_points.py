"""The Saturation tab's "Add my run": the same run again replaces its point; points can be removed."""
from __future__ import annotations

import pytest

from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.live.session import SessionRuns
from ringlab.tabs.saturation import SaturationView


def test_add_again_replaces_and_remove_removes():
    runs = SessionRuns()
    v = SaturationView(runs=runs)
    r = HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5))
    runs.hydro = r
    r.advance(60.0, until=21.0)
    v._add()
    assert len(runs.points) == 1 and "added" in v.message.object
    r.advance(60.0, until=23.0)
    v._add()  # the same run, later: one point, moved
    assert len(runs.points) == 1 and runs.points[0]["orbits"] == pytest.approx(23.0)
    assert "updated your point" in v.message.object
    assert list(v.user_source.data["lambda_p"]) == [runs.points[0]["lambda_p_m"]]
    r.settings.sigma0 = 300.0  # another run (new settings): a second point
    r.advance(60.0, until=21.0)
    v._add()
    assert [p["sigma0"] for p in runs.points] == [400.0, 300.0]
    assert v.point_select.visible and v.remove_button.visible and len(v.point_select.options) == 2
    v.point_select.value = 0
    v._remove()
    assert [p["sigma0"] for p in runs.points] == [300.0]
    assert list(v.user_source.data["sigma0"]) == [300.0] and "removed your point" in v.message.object
    v._remove()
    assert runs.points == [] and not v.remove_button.visible and v.user_source.data["sigma0"] == []
    assert "does not exist" in runs.remove_point(0)
    r.close()
