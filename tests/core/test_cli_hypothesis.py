"""Property-based tests of the command line: generated argument vectors, in-process.

For every command (linear, hydro, nbody, reproduce, resume, sweep) Hypothesis generates argument
vectors mixing valid and invalid values, unknown flags, contradictory combinations, existing
``--out`` files, folders, unwritable places and damaged input files, and runs them through
``ringcore.cli.main.main(argv)``.  Properties:

- no traceback on stderr, exit status 0, 1 or 2; an error is ONE line ``ringcore ...: error: ...``;
- no file that existed before is changed (bytes and mtime), except the one ``--overwrite`` names
  and the file ``ringcore resume FILE`` continues in place;
- generated valid inputs (the ``valid`` strategies: tiny runs) succeed and write their output.

Profiles (``HYPOTHESIS_PROFILE``): ``ci`` (default; fixed example budget, derandomized, < 2 min
in all) and ``long`` (``scripts/hypothesis_long.py``).
"""
import contextlib
import io
import shutil
import tempfile
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ringcore.cli.main import main  # noqa: E402

# profiles "ci" (default) and "long" (HYPOTHESIS_PROFILE=long): tests/conftest.py
# per-command share of the budget (the slow commands get fewer examples)
SCALE = {"linear": 1.5, "hydro": 1.5, "nbody": 1.0, "resume": 1.0, "reproduce": 1.0, "sweep": 0.5}
STATS = {"cases": 0, "by_status": {}, "by_command": {}}


def budget(cmd):
    return settings(max_examples=max(2, int(settings.default.max_examples * SCALE[cmd])))


# ------------------------------------------------------------------ the sandbox of each example
@pytest.fixture(scope="module")
def seed_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("seed")
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        assert main(["hydro", "--lx", "200", "--orbits", "0.02", "--no-progress", "--out", str(d / "h.nc")]) == 0
        assert main(["nbody", "--L-x", "12", "--L-y", "12", "--orbits", "0.02", "--no-progress",
                     "--out", str(d / "n.nc")]) == 0
    raw = (d / "h.nc").read_bytes()
    (d / "damaged.nc").write_bytes(raw[: len(raw) // 2])
    (d / "garbage.nc").write_bytes(b"not a netcdf file at all\n" * 20)
    return d


class Sandbox:
    """A fresh folder per example: run files, a precious file, a sub-folder, a plain file."""

    def __init__(self, seed):
        self.dir = Path(tempfile.mkdtemp(prefix="rc-hyp-"))
        for f in seed.iterdir():
            shutil.copy2(f, self.dir / f.name)
        (self.dir / "precious.nc").write_bytes(b"my result, do not touch")
        (self.dir / "sub").mkdir()
        (self.dir / "plain.txt").write_text("x")
        (self.dir / "out").mkdir()
        for name in ("omega.png", "omega.nc"):
            (self.dir / "out" / name).write_bytes(b"an earlier figure")

    def snapshot(self):
        out = {}
        for p in self.dir.rglob("*"):
            if p.is_file():
                st_ = p.stat()
                out[p] = (p.read_bytes(), st_.st_mtime_ns)
        return out

    def close(self):
        shutil.rmtree(self.dir, ignore_errors=True)


OUT_KINDS = ("new", "new", "new", "existing", "run_file", "folder", "unwritable", "empty", "under_file",
             "missing_folder")


def out_path(sb, kind, ext=".nc"):
    return {"new": str(sb.dir / f"result{ext}"), "existing": str(sb.dir / "precious.nc"),
            "run_file": str(sb.dir / "n.nc"), "folder": str(sb.dir / "sub"), "unwritable": "/proc/ringcore-x.nc",
            "empty": "", "under_file": str(sb.dir / "plain.txt" / "x.nc"),
            "missing_folder": str(sb.dir / "nowhere" / "x.nc")}[kind]


def check(sb, argv, *, valid, may_change=()):
    """Run ``argv`` in ``sb`` and check the properties; returns the exit status."""
    before = sb.snapshot()
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        rc = main(argv)
    err = err.getvalue()
    STATS["cases"] += 1
    STATS["by_status"][rc] = STATS["by_status"].get(rc, 0) + 1
    key = f"{argv[0] if argv else '-'}:{rc}"
    STATS["by_command"][key] = STATS["by_command"].get(key, 0) + 1
    assert "Traceback" not in err, (argv, err)
    assert rc in (0, 1, 2), (argv, rc, err)
    if rc:
        lines = [ln for ln in err.strip().splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("ringcore") and "error" in lines[0], (argv, err)
    allowed = {Path(p) for p in may_change}
    after = sb.snapshot()
    for p, fp in before.items():
        if p not in allowed:
            assert after.get(p) == fp, (argv, f"{p} changed or vanished")
    if valid:
        assert rc == 0, (argv, err)
    return rc


# ------------------------------------------------------------------ value strategies
BAD_NUM = st.sampled_from(["nan", "inf", "-inf", "-1", "0", "1e308", "abc", "", "1e-300", "--"])
UNKNOWN = st.sampled_from(["--bogus", "-z", "--out=", "--orbit", "--sigma", "---", "extra"])


def opt(name, good, bad=BAD_NUM, p_bad=0.3):
    """An optional (flag, value) pair: absent, a good value or a bad one."""
    return st.one_of(st.just([]), st.tuples(st.just(name), good).map(list),
                     st.tuples(st.just(name), bad).map(list)) if p_bad else \
        st.one_of(st.just([]), st.tuples(st.just(name), good).map(list))


def flat(parts):
    return [str(x) for part in parts for x in part]


SETS = st.sampled_from(["tau10", "tau15", "tau20", "tau15_oz2", "tau20_oz2", "st99"])
RING_VALID = st.tuples(
    st.one_of(st.just([]), st.tuples(st.just("--set"), SETS.filter(lambda s: s != "st99")).map(list)),
    st.one_of(st.just([]), st.tuples(st.just("--sigma0"), st.sampled_from(["0", "100", "400", "700"])).map(list)),
    st.one_of(st.just([]), st.tuples(st.just("--ps-scale"), st.sampled_from(["1", "1.4", "2"])).map(list)),
    st.one_of(st.just([]), st.tuples(st.just("--beta"), st.sampled_from(["1.19", "0.5", "-0.5"])).map(list)),
)
RING_MIXED = st.tuples(
    opt("--set", SETS, st.sampled_from(["tau99", "", "ST99"])),
    opt("--sigma0", st.sampled_from(["0", "400", "5000", "1e20"])),
    st.one_of(st.just([]), st.just(["--isothermal"])),
    opt("--ps", st.sampled_from(["1", "2.41"])),
    opt("--ps-scale", st.sampled_from(["1", "1.4"])),
    opt("--beta", st.sampled_from(["1.19", "-0.99"])),
)


# ------------------------------------------------------------------ linear
@budget("linear")
@given(ring=RING_MIXED, js=st.booleans(), junk=st.one_of(st.just([]), UNKNOWN.map(lambda u: [u])))
def test_linear_mixed(seed_files, ring, js, junk):
    sb = Sandbox(seed_files)
    try:
        check(sb, ["linear"] + flat(ring) + (["--json"] if js else []) + junk, valid=False)
    finally:
        sb.close()


@budget("linear")
@given(ring=RING_VALID, iso=st.booleans(), js=st.booleans())
def test_linear_valid(seed_files, ring, iso, js):
    sb = Sandbox(seed_files)
    try:
        check(sb, ["linear"] + flat(ring) + (["--isothermal"] if iso else []) + (["--json"] if js else []), valid=True)
    finally:
        sb.close()


# ------------------------------------------------------------------ hydro
HYDRO_OPTS = st.tuples(
    opt("--h", st.sampled_from(["2.5", "5", "12.5"])),
    opt("--seed", st.sampled_from(["0", "3"]), st.sampled_from(["-1", "x", "1.5"])),
    opt("--amplitude", st.sampled_from(["1e-4", "1e-3"])),
    opt("--lambda-min", st.sampled_from(["50", "20", "4"])),
    opt("--init", st.sampled_from(["noise", "mode", "ground"]), st.sampled_from(["wave", "", "h.nc", "garbage.nc"])),
    opt("--wavelength", st.sampled_from(["100", "50", "3"])),
    opt("--direction", st.sampled_from(["left", "right"]), st.sampled_from(["up", ""])),
    opt("--gravity", st.sampled_from(["mode", "wire"]), st.sampled_from(["fft", ""])),
    opt("--replicas", st.sampled_from(["0", "2"]), st.sampled_from(["-1", "x"])),
    st.one_of(st.just([]), st.just(["--bin-correction"])),
    opt("--timestep", st.sampled_from(["paper", "cfl"]), st.sampled_from(["fast", ""])),
    opt("--T-floor", st.sampled_from(["0", "0.01"]), st.sampled_from(["2", "-0.1", "nan"])),
    opt("--buffer", st.sampled_from(["-50 0 -0.5"]), st.sampled_from(["0 -50 -0.5", "a b c"])),
    opt("--buffer-on", st.sampled_from(["0", "0.01"])),
    opt("--samples", st.sampled_from(["10", "20"]), st.sampled_from(["0", "-3", "x"])),
    opt("--spacetime-rows", st.sampled_from(["0", "5"]), st.sampled_from(["3", "-1"])),
    opt("--checkpoint-every", st.sampled_from(["0.01"])),
    opt("--dt-factor", st.sampled_from(["0.1", "1.1"]), st.sampled_from(["0", "11", "nan"])),
)


def _split(parts):
    out = []
    for x in flat(parts):
        out += x.split(" ") if x.count(" ") == 2 else [x]
    return out


@budget("hydro")
@given(ring=RING_MIXED, extra=HYDRO_OPTS, lx=opt("--lx", st.sampled_from(["200", "250"]), p_bad=0.3),
       orbits=st.sampled_from(["0.01", "0.02", "-1", "0", "nan", "1e13"]), out=st.sampled_from(OUT_KINDS),
       overwrite=st.booleans(), junk=st.one_of(st.just([]), UNKNOWN.map(lambda u: [u])))
def test_hydro_mixed(seed_files, ring, extra, lx, orbits, out, overwrite, junk):
    sb = Sandbox(seed_files)
    try:
        lx = lx or ["--lx", "200"]  # never the 5 km default: examples stay tiny
        argv = ["hydro"] + flat(ring) + _split(extra) + lx + ["--orbits", orbits, "--no-progress"] + junk
        argv = [a.replace("h.nc", str(sb.dir / "h.nc")).replace("garbage.nc", str(sb.dir / "garbage.nc"))
                for a in argv]
        target = out_path(sb, out)
        argv += ["--out", target] + (["--overwrite"] if overwrite else [])
        check(sb, argv, valid=False, may_change=[target] if overwrite else [])
    finally:
        sb.close()


@budget("hydro")
@given(ring=RING_VALID, init=st.sampled_from(["noise", "mode", "ground"]), iso=st.booleans(),
       orbits=st.sampled_from(["0.01", "0.02"]), lx=st.sampled_from(["200", "400"]),
       gravity=st.sampled_from(["mode", "wire"]), over=st.booleans())
def test_hydro_valid(seed_files, ring, init, iso, orbits, lx, gravity, over):
    sb = Sandbox(seed_files)
    try:
        argv = ["hydro"] + flat(ring) + ["--init", init, "--lx", lx, "--orbits", orbits, "--no-progress"]
        argv += ["--isothermal"] if iso else []
        if init == "mode":
            argv += ["--wavelength", "100"]
        sigma0 = ring[1][1] if ring[1] else "400"
        if gravity == "wire" and sigma0 != "0":
            argv += ["--gravity", "wire"]
        target = out_path(sb, "existing" if over else "new")
        argv += ["--out", target] + (["--overwrite"] if over else [])
        check(sb, argv, valid=True, may_change=[target])
        assert Path(target).read_bytes()[:4] == b"\x89HDF"
    finally:
        sb.close()


# ------------------------------------------------------------------ nbody
NBODY_OPTS = st.tuples(
    opt("--set", SETS, st.sampled_from(["tau99"])),
    opt("--sigma0", st.sampled_from(["0", "100"]), st.sampled_from(["-5", "1e20", "1e14", "nan"])),
    opt("--R-p", st.sampled_from(["1"]), st.sampled_from(["0", "-1", "100"])),
    opt("--restitution", st.sampled_from(["bridges", "constant"]), st.sampled_from(["elastic", ""])),
    opt("--epsilon", st.sampled_from(["0.5"]), st.sampled_from(["0", "1.5"])),
    opt("--dt", st.sampled_from(["1e-3", "2e-3"]), st.sampled_from(["0", "1", "-1e-3"])),
    opt("--equilibrate", st.sampled_from(["0", "0.01"]), st.sampled_from(["-5", "nan"])),
    opt("--seed", st.sampled_from(["0", "7"]), st.sampled_from(["-1", "x"])),
    opt("--m-max", st.sampled_from(["8"]), st.sampled_from(["0", "-1"])),
    opt("--single-mode", st.sampled_from(["0", "1"]), st.sampled_from(["-1"])),
    opt("--seed-mode", st.sampled_from(["0", "1", "2"]), st.sampled_from(["-2", "100"])),
    opt("--amplitude", st.sampled_from(["1"])),
    opt("--fill-fraction", st.sampled_from(["1", "0.8"]), st.sampled_from(["0", "2"])),
    opt("--from", st.sampled_from(["n.nc"]), st.sampled_from(["h.nc", "garbage.nc", "damaged.nc", "missing.nc", ""])),
    st.one_of(st.just([]), st.just(["--tile-x"])),
    opt("--record-every", st.sampled_from(["0.01"]), st.sampled_from(["0", "1e-9"])),
    opt("--profile-every", st.sampled_from(["0.01"])),
    st.one_of(st.just([]), st.just(["--json"])),
)


@budget("nbody")
@given(extra=NBODY_OPTS, box=st.sampled_from([("12", "12"), ("16", "12"), ("4", "12"), ("1e6", "1e6"), ("nan", "12")]),
       orbits=st.sampled_from(["0.01", "0.02", "-1", "inf"]), out=st.sampled_from(OUT_KINDS), overwrite=st.booleans(),
       junk=st.one_of(st.just([]), UNKNOWN.map(lambda u: [u])))
def test_nbody_mixed(seed_files, extra, box, orbits, out, overwrite, junk):
    sb = Sandbox(seed_files)
    try:
        argv = ["nbody"] + flat(extra) + ["--L-x", box[0], "--L-y", box[1], "--orbits", orbits, "--no-progress"]
        argv = [str(sb.dir / a) if a.endswith(".nc") else a for a in argv] + junk
        target = out_path(sb, out)
        argv += ["--out", target] + (["--overwrite"] if overwrite else [])
        check(sb, argv, valid=False, may_change=[target] if overwrite else [])
    finally:
        sb.close()


@budget("nbody")
@given(set_=SETS.filter(lambda s: s != "st99"), sigma0=st.sampled_from(["0", "100", "400"]),
       restitution=st.sampled_from(["bridges", "constant"]), equilibrate=st.sampled_from(["0", "0.01"]),
       seed_mode=st.sampled_from(["0", "2"]), from_file=st.booleans())
def test_nbody_valid(seed_files, set_, sigma0, restitution, equilibrate, seed_mode, from_file):
    sb = Sandbox(seed_files)
    try:
        target = out_path(sb, "new")
        if from_file:
            argv = ["nbody", "--from", str(sb.dir / "n.nc"), "--sigma0", sigma0]
        else:
            argv = ["nbody", "--set", set_, "--sigma0", sigma0, "--restitution", restitution, "--L-x", "12",
                    "--L-y", "12"] + (["--seed-mode", seed_mode] if seed_mode != "0" else [])
        argv += ["--orbits", "0.01", "--equilibrate", equilibrate, "--no-progress", "--out", target]
        check(sb, argv, valid=True)
        assert Path(target).exists()
    finally:
        sb.close()


# ------------------------------------------------------------------ resume
@budget("resume")
@given(src=st.sampled_from(["h.nc", "n.nc", "damaged.nc", "garbage.nc", "missing.nc", "sub", "precious.nc", ""]),
       when=st.sampled_from([["--orbits", "0.01"], ["--until", "0.03"], ["--until", "0.001"], ["--orbits", "-1"],
                             ["--orbits", "nan"], [], ["--orbits", "0.01", "--until", "1"]]),
       out=st.sampled_from(("inplace",) + OUT_KINDS), overwrite=st.booleans(),
       junk=st.one_of(st.just([]), UNKNOWN.map(lambda u: [u])))
def test_resume_mixed(seed_files, src, when, out, overwrite, junk):
    sb = Sandbox(seed_files)
    try:
        f = str(sb.dir / src) if src else ""
        argv = ["resume", f] + when + ["--no-progress"] + junk
        may = []
        if out == "inplace":
            may = [f]
        else:
            target = out_path(sb, out)
            argv += ["--out", target] + (["--overwrite"] if overwrite else [])
            may = [target] if overwrite else []
            if target == f:  # --out FILE itself: resuming in place (found by the long profile: oracle fixed)
                may = [f]
        check(sb, argv, valid=False, may_change=may)
    finally:
        sb.close()


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
@budget("resume")
@given(src=st.sampled_from(["h.nc", "n.nc"]), how=st.sampled_from(["inplace", "new", "overwrite"]),
       when=st.sampled_from([["--orbits", "0.01"], ["--until", "0.03"]]))
def test_resume_valid(seed_files, src, how, when):
    sb = Sandbox(seed_files)
    try:
        f = str(sb.dir / src)
        argv, may = ["resume", f] + when + ["--no-progress", "--json"], [f]
        if how != "inplace":
            target = out_path(sb, "new" if how == "new" else "existing")
            argv += ["--out", target] + (["--overwrite"] if how == "overwrite" else [])
            may = [target]
        check(sb, argv, valid=True, may_change=may)
    finally:
        sb.close()


# ------------------------------------------------------------------ reproduce
@budget("reproduce")
@given(name=st.sampled_from(["omega", "vgroup", "nonexistent", "", "--list"]),
       mode=st.sampled_from([[], ["--quick"], ["--full"], ["--quick", "--full"]]),
       out=st.sampled_from(["out", "plain", "unwritable", "empty", "under_file"]), lst=st.booleans(),
       junk=st.one_of(st.just([]), UNKNOWN.map(lambda u: [u])))
def test_reproduce_mixed(seed_files, name, mode, out, lst, junk):
    """Never a real recipe run: 'out' already holds omega's outputs, the other places are unusable."""
    sb = Sandbox(seed_files)
    try:
        if name == "vgroup" and out == "out" and not lst:
            name = "omega"  # keep it a refusal (vgroup would really run)
        o = {"out": str(sb.dir / "out"), "plain": str(sb.dir / "plain.txt"), "unwritable": "/proc/rc-out",
             "empty": "", "under_file": str(sb.dir / "plain.txt" / "x")}[out]
        argv = ["reproduce"] + ([name] if name else []) + mode + ["--out", o] + (["--list"] if lst else []) + junk
        check(sb, argv, valid=False)
    finally:
        sb.close()


def test_reproduce_list_valid(seed_files):
    sb = Sandbox(seed_files)
    try:
        check(sb, ["reproduce", "--list"], valid=True)
    finally:
        sb.close()


# ------------------------------------------------------------------ sweep
@budget("sweep")
@given(engine=st.sampled_from(["linear", "hydro", "nbody", "gpu"]),
       sigma0=st.sampled_from(["0", "100,200", "0:200:100", "5:1:1", "a,b", "0:1e9:1e-3", ""]),
       extra=st.tuples(opt("--ps-scale", st.sampled_from(["1", "1,1.4"]), st.sampled_from(["0", "x"])),
                       opt("--h", st.sampled_from(["2.5"])), opt("--workers", st.sampled_from(["1"]),
                                                                  st.sampled_from(["0", "-2"])),
                       opt("--scheduler", st.sampled_from(["notanaddress"]), st.sampled_from(["tcp://:x", ""]))),
       out=st.sampled_from(["plain", "unwritable", "empty", "under_file"]))
def test_sweep_mixed(seed_files, engine, sigma0, extra, out):
    """Invalid places or values only: a valid sweep starts a cluster (see test_cli_safety for those)."""
    sb = Sandbox(seed_files)
    try:
        o = {"plain": str(sb.dir / "plain.txt"), "unwritable": "/proc/rc-sweep", "empty": "",
             "under_file": str(sb.dir / "plain.txt" / "x")}[out]
        argv = ["sweep", "--engine", engine, "--sigma0", sigma0, "--orbits", "0.01", "--lx", "200"]
        argv = argv + flat(extra) + ["--out", o]
        rc = check(sb, argv, valid=False)
        assert rc != 0
    finally:
        sb.close()


def test_report_counts(capsys):
    """Prints how many generated cases ran (shown with -s; scripts/hypothesis_long.py reports it)."""
    with capsys.disabled():
        print(f"\nhypothesis CLI cases run: {STATS['cases']} (exit statuses {STATS['by_status']}; "
              f"command:status {dict(sorted(STATS['by_command'].items()))})")
