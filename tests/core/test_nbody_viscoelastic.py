"""Visco-elastic impacts of finite duration (NBodyOptions(impacts="viscoelastic")): the restitution law and
the contact duration of a head-on impact, its energy and momentum bookkeeping, the chosen time step, restarts
bit for bit, and the ground state against Table "Hydrodynamic Parameters"."""
import math

import numpy as np
import pytest

from ringcore import params
from ringcore.nbody import NBodyOptions, ShearingBox
from ringcore.nbody import viscoelastic as V

TAU15 = params.get("tau15")


def head_on(v_over_vc, law, phase=0.3, b=0.0, v_t=0.0, **kw):
    """Two particles approaching along y at normal speed v = v_over_vc v_c (impact parameter ``b`` [R_p],
    tangential relative speed ``v_t`` [R_p Omega] along z), run until they part.  Returns the box, the
    speed v [R_p Omega], the measured restitution, the contact duration [orbits] and the energies."""
    o = NBodyOptions(L_x=20, L_y=20, impacts="viscoelastic", restitution=law, **kw)
    v = v_over_vc * o.v_c / (o.R_p * TAU15.Omega)
    dt = 2.0 * math.pi * o.dt_orbit
    s = math.sqrt(4.0 - b * b) + phase * v * dt  # touching after `phase` of a step
    pos = np.array([[0.0, -0.5 * s, -0.5 * b], [0.0, 0.5 * s, 0.5 * b]])
    vel = np.array([[0.0, 0.5 * v, -0.5 * v_t], [0.0, -0.5 * v, 0.5 * v_t]])
    box = ShearingBox(TAU15, o, state=(pos, vel, 0.0))
    e0 = 0.5 * float((box.vel ** 2).sum())
    n_in = None
    for k in range(40 * o.contact_steps):
        n0 = np.array(box.pos[1] - box.pos[0])
        box.step()
        r = np.linalg.norm(box.pos[1] - box.pos[0])
        if n_in is None and r < 2.0:
            n_in = k
        elif n_in is not None and r >= 2.0:
            break
    else:
        raise AssertionError("the contact did not end")
    d = box.pos[1] - box.pos[0]
    n = d / np.linalg.norm(d)
    eps = float((box.vel[1] - box.vel[0]) @ n) / v if b == 0 else None
    return dict(box=box, v=v, eps=eps, duration=(k - n_in) * o.dt_orbit, e0=e0,
                e1=0.5 * float((box.vel ** 2).sum()), n0=n0)


@pytest.mark.parametrize("law", ["bridges", "constant"])
def test_head_on_impact_returns_restitution_law_and_duration(law):
    """0.01 - 10 v_c, contacts starting anywhere in a step: eps within 1 % of the law, duration T_c +- 1 step."""
    o = NBodyOptions(impacts="viscoelastic")
    for f, phase in zip((0.01, 0.03, 0.1, 0.3, 1.0, 2.0, 3.0, 5.0, 10.0), (0.1, 0.3, 0.7, 0.9, 0.2, 0.6, 0.4, 0.8, 0.3)):
        r = head_on(f, law, phase)
        ref = 0.5 if law == "constant" else min(1.0, f ** -0.234)
        assert r["eps"] == pytest.approx(ref, rel=0.01), (f, phase)
        assert abs(r["duration"] - o.contact_duration) <= 1.01 * o.dt_orbit, (f, r["duration"])


def test_single_impact_energy_and_momentum_bookkeeping():
    """Momentum conserved to round-off; the kinetic energy lost is (1 - eps^2) of the normal relative motion's
    (v^2/4 per unit mass) and equals the dashpot work counted by the kernel; an oblique impact keeps its
    tangential relative velocity."""
    r = head_on(2.0, "constant", 0.45)
    box, v = r["box"], r["v"]
    np.testing.assert_allclose(box.vel.sum(0), 0.0, atol=1e-15 * v)
    lost = (1.0 - 0.5**2) * 0.25 * v * v
    assert r["e0"] - r["e1"] == pytest.approx(lost, rel=0.01)
    assert box._contacts[3][V.S_DISSIPATED] == pytest.approx(r["e0"] - r["e1"], rel=0.01)
    assert box._contacts[3][V.S_STARTED] == 1 and box.acc_total[0] == 1  # one impact, counted once
    ob = head_on(1.0, "constant", 0.3, b=1.0, v_t=0.2 * 1.0 * NBodyOptions().v_c / TAU15.Omega)
    np.testing.assert_allclose(ob["box"].vel.sum(0), 0.0, atol=1e-15)
    assert ob["e1"] < ob["e0"]


def test_time_step_is_chosen_and_bad_options_named():
    o = NBodyOptions(impacts="viscoelastic")
    assert o.dt_orbit == pytest.approx(o.contact_duration / 20) and o.contact_steps == 20
    assert NBodyOptions().dt_orbit == 1e-3
    assert NBodyOptions(impacts="viscoelastic", contact_duration=2e-3).dt_orbit == pytest.approx(1e-4)
    assert NBodyOptions().replace(impacts="viscoelastic").dt_orbit == pytest.approx(1.25e-5)
    with pytest.raises(ValueError, match="dt_orbit = 0.001 is out of range"):
        NBodyOptions(impacts="viscoelastic", dt_orbit=1e-3)
    with pytest.raises(ValueError, match="impacts"):
        NBodyOptions(impacts="soft")
    with pytest.raises(ValueError, match="contact_duration"):
        NBodyOptions(impacts="viscoelastic", contact_duration=0.5)


def test_restart_from_run_file_continues_bit_for_bit(tmp_path):
    """Contact memory travels with the state: a run saved mid-contacts continues identically."""
    o = NBodyOptions(L_x=20, L_y=12, impacts="viscoelastic", contact_duration=2e-3, record_every=0.01,
                     profile_every=0.02)
    box = ShearingBox(TAU15.with_sigma0(300), o, seed=3)
    box.advance(0.03)
    assert (box._contacts[1] == box.steps - 1).sum() > 5  # contacts in progress at the save
    path = tmp_path / "v.nc"
    box.save(path)
    again = ShearingBox.load(path)
    snap = ShearingBox.restore(box.snapshot())
    for b in (box, again, snap):
        b.advance(0.02)
    for b in (again, snap):
        np.testing.assert_array_equal(b.pos, box.pos)
        np.testing.assert_array_equal(b.vel, box.vel)
        for c, c0 in zip(b._contacts, box._contacts):
            np.testing.assert_array_equal(c, c0)
        np.testing.assert_array_equal(b.acc, box.acc)
    assert again.options == box.options and again.options.impacts == "viscoelastic"


def test_calls_split_anyhow_are_bit_identical():
    o = NBodyOptions(L_x=16, L_y=16, impacts="viscoelastic", contact_duration=2e-3)
    a = ShearingBox(TAU15, o, seed=2)
    b = ShearingBox(TAU15, o, seed=2)
    a._advance_steps(300)
    for n in (1, 7, 92, 200):
        b._advance_steps(n)
    np.testing.assert_array_equal(a.pos, b.pos)
    np.testing.assert_array_equal(a.vel, b.vel)


def settled_ground_state(set_name, contact_duration=None, L=20.0, orbits=2.0, seed=1):
    """Transport (SI) of a visco-elastic box of ``L`` m x ``L`` m settled for 2 orbits with instantaneous impacts
    (cheap) and 0.25 orbit with contacts of ``contact_duration`` (None: the default), averaged over ``orbits``."""
    p = params.get(set_name)
    pre = ShearingBox(p, NBodyOptions(L_x=L, L_y=L, record_every=1.0, profile_every=0.0), seed=seed, threads=1)
    pre.advance(2.0)
    kw = {} if contact_duration is None else dict(contact_duration=contact_duration)
    o = NBodyOptions(L_x=L, L_y=L, impacts="viscoelastic", record_every=0.25, profile_every=0.0, **kw)
    box = ShearingBox(p, o, seed=seed, state=(pre.pos, pre.vel, pre._t0 + pre.steps * pre.dt), ids=pre.ids,
                      threads=1)
    box.advance(0.25)
    box.reset_accumulators()
    box.advance(orbits)
    return p, box.transport()


@pytest.mark.slow  # 43 s of CPU on the loaded 2-core machine (2.25 orbits of 80,000 steps, 255 particles)
def test_ground_state_matches_table_viscoelastic():
    """tau = 2, Omega_z = 3.6 (the densest set, where the contact duration matters most), Bridges law, default
    contact duration, 20 m x 20 m: T, nu, c0 of Table "Hydrodynamic Parameters" within 3 %.  With the former
    default T_c = 1e-3 orbit this fails (T +8.8 %, nu +0.6 %, c0 +1.0 %; docs "Departures").  The 2-orbit average
    has a standard error of about 0.65 % in T, 1.2 % in nu and 0.4 % in c0 (block averages)."""
    p, tr = settled_ground_state("tau20")
    assert tr["T"] == pytest.approx(p.T0, rel=0.03)  # measured +2.4 %
    assert tr["nu"] == pytest.approx(p.nu0, rel=0.03)  # -0.1 %
    assert tr["c_eff"] == pytest.approx(p.c0, rel=0.03)  # +0.3 %
    assert tr["unresolved"] == 0 and 0 < tr["max_overlap"] < 0.05


def test_cli_impacts_option_states_the_time_step(tmp_path, capsys):
    import json

    import xarray as xr

    from ringcore.cli.main import main
    out = tmp_path / "v.nc"
    rc = main(["nbody", "--impacts", "viscoelastic", "--L-x", "12", "--L-y", "12", "--orbits", "0.01",
               "--record-every", "0.005", "--profile-every", "0.01", "--out", str(out), "--no-progress"])
    assert rc == 0
    text = capsys.readouterr().out
    assert "contacts of 0.00025 orbits; time step 1.25e-05 orbits (20 steps per contact, 80,000 per orbit)" in text
    ds = xr.load_dataset(out, engine="h5netcdf")
    assert ds.attrs["option_impacts"] == "viscoelastic" and ds.attrs["option_dt_orbit"] == pytest.approx(1.25e-5)
    assert "contact_eps" in ds and ds.attrs["step_count"] == 800
    rc = main(["nbody", "--from", str(out), "--orbits", "0.005", "--out", str(tmp_path / "w.nc"), "--no-progress",
               "--json"])
    assert rc == 0 and json.loads(capsys.readouterr().out)["impacts"] == "viscoelastic"
    for argv, msg in ((["--impacts", "soft"], "--impacts"),
                      (["--contact-duration", "2e-3"], "--contact-duration has no effect with --impacts instant"),
                      (["--impacts", "viscoelastic", "--dt", "1e-3"], "--dt = 0.001 orbits is out of range"),
                      (["--impacts", "viscoelastic", "--contact-duration", "1"], "--contact-duration")):
        assert main(["nbody", *argv, "--orbits", "0.01", "--no-progress", "--out", str(tmp_path / "x.nc")]) == 2
        err = capsys.readouterr().err
        assert msg in err and len(err.strip().splitlines()) == 1, err


def test_validate_command_prints_both_models_with_error_bars(tmp_path, capsys):
    """`ringcore validate nbody-impacts --what groundstate` on a tiny box: a row per quantity with both models,
    error bars and the visco/instant ratio; the JSON rows; a bad --blocks is refused in one line."""
    import json

    from ringcore.cli.main import main
    out = tmp_path / "v.json"
    rc = main(["validate", "nbody-impacts", "--what", "groundstate", "--sets", "tau20_oz2", "--L-x", "8", "--L-y", "8",
               "--equilibrate", "0.05", "--resettle", "0.005", "--blocks", "2", "--block-orbits", "0.005",
               "--contact-duration", "2e-3", "--json", str(out)])
    text = capsys.readouterr().out
    assert rc == 1 and text.strip().endswith("FAIL")  # far from the table after 0.06 orbits
    rows = [line for line in text.splitlines() if line.startswith(" 2.0  2.0 ")]
    assert [r.split()[2] for r in rows] == ["T", "nu", "c0"] and all(r.count("+-") == 4 for r in rows)
    data = json.loads(out.read_text())
    vi, ve = data["groundstate tau20_oz2 instant"], data["groundstate tau20_oz2 viscoelastic"]
    assert vi["dt_orbit"] == pytest.approx(1e-3) and ve["dt_orbit"] == pytest.approx(1e-4)
    assert ve["T_err"] > 0 and ve["N"] == vi["N"] == 41
    assert main(["validate", "nbody-impacts", "--blocks", "1"]) == 2
    err = capsys.readouterr().err
    assert "--blocks = 1 is out of range" in err and len(err.strip().splitlines()) == 1
    assert main(["validate", "nbody-impacts", "--what", "growth", "--settle", "-1"]) == 2
    err = capsys.readouterr().err
    assert "--settle = -1" in err and len(err.strip().splitlines()) == 1
