#!/usr/bin/env bash
# Runs the long paper-scale hydro runs of one lane sequentially (niced), from a frozen copy of the code.
# usage: lane.sh NAME:ORBITS:ARGS... ; each run writes $LONGRUNS/NAME.nc (checkpoint every 200 orbits);
# LONGRUNS defaults to runs/longruns of this checkout, PY to its .venv/bin/python, the code to $LONGRUNS/code.
REPO=$(cd "$(dirname "$0")/../.." && pwd)
DIR=${LONGRUNS:-$REPO/runs/longruns}
cd "$DIR" || exit 1
export PYTHONPATH=${RINGCORE_CODE:-$DIR/code}
PY=${PY:-$REPO/.venv/bin/python}
for spec in "$@"; do
  name=${spec%%|*}; rest=${spec#*|}
  if [ -f "$name.nc" ]; then
    echo "$(date -u +%FT%TZ) resume $name" >> "$name.log"
    nice -n 19 $PY -m ringcore.cli.main resume "$name.nc" --until ${rest%%|*} --no-progress >> "$name.log" 2>&1 || nice -n 19 $PY -m ringcore.cli.main resume "$name.nc" --until ${rest%%|*} >> "$name.log" 2>&1
  else
    echo "$(date -u +%FT%TZ) start $name: ${rest#*|}" >> "$name.log"
    nice -n 19 $PY -m ringcore.cli.main hydro ${rest#*|} --orbits ${rest%%|*} --out "$name.nc" --checkpoint-every 200 --no-progress >> "$name.log" 2>&1
  fi
  echo "$(date -u +%FT%TZ) end $name status $?" >> "$name.log"
done
