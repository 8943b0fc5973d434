"""The page's controls stay inside the physical ranges of the numerical core (ringcore.ranges is the one
source of truth): whatever a slider or an uploaded settings file can hold, the engine accepts, and what the
engine refuses the page names before starting a run."""
import math

import param
import pytest

from ringcore import params, ranges
from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.model.nbody_settings import NBodySettings

# page parameter -> name in ringcore.ranges
HYDRO = {"sigma0": "sigma0", "ps_scale": "ps_scale", "L_x": "L_x", "h": "h", "seed": "seed",
         "wavelength": "wavelength_m", "buffer_width": "L_x"}
NBODY = {"sigma0": "sigma0", "L_x": "L_x", "L_y": "L_y", "seed": "seed"}


def _inside(bounds, rng, name):
    lo, hi = bounds
    assert lo >= rng.lo and hi <= rng.hi, f"{name}: page bounds {bounds} outside the core's {rng.lo} .. {rng.hi}"
    if rng.lo_open:
        assert lo > rng.lo or name in ("sigma0", "buffer_width"), f"{name}: {lo} is excluded by the core"


@pytest.mark.parametrize("cls, table", [(HydroSettings, HYDRO), (NBodySettings, NBODY)])
def test_every_numeric_control_lies_inside_the_core_range(cls, table):
    for pname, rname in table.items():
        p = cls.param[pname]
        assert isinstance(p, (param.Number, param.Integer))
        _inside(p.bounds, ranges.get(rname), pname)


def test_page_sigma0_maximum_is_allowed_for_every_parameter_set():
    hi = HydroSettings.param["sigma0"].bounds[1]
    for name in params.SET_NAMES:
        p = params.get(name)
        assert hi <= ranges.sigma0_max(p.Omega, p.c0), name


def test_white_noise_amplitude_beyond_the_core_range_is_named_before_a_run():
    r = HydroRunner()
    r.settings.initial = "noise"
    r.settings.amplitude = math.nextafter(ranges.get("amplitude_noise").hi, 1.0)
    msg = r.settings.find_problems().get("initial", "")
    assert "amplitude" in msg and "0.1" in msg
