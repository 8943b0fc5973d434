#!/usr/bin/env bash
# Continue the paper's long hydro runs in a new session (issue 13 item 3), from where the checkpoints stopped.
# Same runs, names and settings as the lead's lane.sh (started 08:31 UTC on 2026-11-23), but every resumed run
# also checkpoints every 200 orbits (lane.sh resumes without --checkpoint-every, so a resumed run would only be
# saved at its end or on SIGTERM).
#
#   campaigns/longruns/resume_lanes.sh 1|2|3    # run one lane in the foreground (use nohup ... & for background)
#   DRY=1 campaigns/longruns/resume_lanes.sh 1  # print the commands only
# A run with no file in $LONGRUNS but a carry file in campaigns/longruns/carry/ (a new machine) starts from
# that file: bit for bit the uninterrupted run (python campaigns/longruns/carry.py writes them before a stop).
#
# Runs niced (nice -n 19) from the frozen code copy $LONGRUNS/code (PYTHONPATH), files in $LONGRUNS
# (default runs/longruns of this checkout; PY defaults to this checkout's .venv/bin/python).
set -u
# nice only orders processes inside one autogroup (Linux CONFIG_SCHED_AUTOGROUP, on here): a lane started with
# setsid/nohup is its own group and would take a full share of the cores from the app and the tests. Lower the
# group's weight too.
echo 19 > /proc/self/autogroup 2>/dev/null || true
REPO=$(cd "$(dirname "$0")/../.." && pwd)
DIR=${LONGRUNS:-$REPO/runs/longruns}
PY=${PY:-$REPO/.venv/bin/python}
export PYTHONPATH=${RINGCORE_CODE:-$DIR/code}
COMMON="--sigma0 0 --lx 10000 --h 2.5 --timestep cfl --samples 10"
LANE1=("iso_tau15_mode100|20000|--set tau15 --isothermal $COMMON --init mode --wavelength 100 --amplitude 1e-3"
       "iso_st99_mode100|20000|--set st99 --isothermal $COMMON --init mode --wavelength 100 --amplitude 1e-3")
# noniso_tau15_noise moved from lane 1 to the end of lane 2 (session 4): lane 2 frees up hours before lane 1.
LANE2=("iso_tau20_mode100|20000|--set tau20 --isothermal $COMMON --init mode --wavelength 100 --amplitude 1e-3"
       "noniso_tau20_noise|14000|--set tau20 $COMMON --init noise --seed 1 --T-floor 0.01"
       "iso_tau15_buffer|20000|--set tau15 --isothermal $COMMON --init noise --seed 1 --buffer -1250 1250 -0.5"
       "noniso_tau15_noise|14000|--set tau15 $COMMON --init noise --seed 1 --T-floor 0.01")
# lane 3 (session 4): the tau20 non-isothermal run on the grid it needs (h = 1.25 m; README, "Departures"), ~20 h
LANE3=("noniso_tau20_h125|14000|--set tau20 --sigma0 0 --lx 10000 --h 1.25 --timestep cfl --samples 10 --init noise --seed 1 --T-floor 0.01")
case "${1:-}" in 1) RUNS=("${LANE1[@]}") ;; 2) RUNS=("${LANE2[@]}") ;; 3) RUNS=("${LANE3[@]}") ;;
  *) echo "usage: $0 1|2|3" >&2; exit 2 ;; esac
# carry files (campaigns/longruns/carry.py): runs carried over from an earlier session's machine, continued bit for bit
CARRY=${CARRY:-$(cd "$(dirname "$0")" && pwd)/carry}
cd "$DIR" || exit 1
for spec in "${RUNS[@]}"; do
  IFS='|' read -r name target opts <<<"$spec"
  if [ ! -f "$name.nc" ] && [ -f "$CARRY/$name.nc" ]; then
    cp "$CARRY/$name.nc" "$name.nc" && echo "$(date -u +%FT%TZ) $name: continued from the carry file $CARRY/$name.nc" >> "$name.log"
  fi
  if [ -f "$name.nc" ]; then
    t=$("$PY" -c "import sys, xarray as xr; print(float(xr.open_dataset(sys.argv[1]).attrs['time_orbits']))" "$name.nc")
    if awk "BEGIN{exit !($t >= $target)}"; then echo "$name: done ($t orbits)"; continue; fi
    # a run that blew up would blow up again at the same step: skip it (its file keeps the last good state)
    if "$PY" -c "import sys, xarray as xr; sys.exit('blowup' not in xr.open_dataset(sys.argv[1]).attrs)" "$name.nc"; then
      echo "$name: skipped, blew up at $t orbits (see its 'blowup' attribute)"; continue; fi
    cmd="nice -n 19 $PY -m ringcore.cli.main resume $name.nc --until $target --checkpoint-every 200 --no-progress"
  else
    cmd="nice -n 19 $PY -m ringcore.cli.main hydro $opts --orbits $target --out $name.nc --checkpoint-every 200 --no-progress"
  fi
  if [ -n "${DRY:-}" ]; then echo "$cmd"; continue; fi
  echo "$(date -u +%FT%TZ) start $name: $cmd" >> "$name.log"
  $cmd >> "$name.log" 2>&1
  echo "$(date -u +%FT%TZ) end $name status $?" >> "$name.log"
done
