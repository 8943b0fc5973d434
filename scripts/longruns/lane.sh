#!/usr/bin/env bash
# Runs the long paper-scale hydro runs of one lane sequentially (niced), from a frozen copy of the code.
# usage: lane.sh NAME:ORBITS:ARGS... ; each run writes /work/longruns/NAME.nc (checkpoint every 200 orbits).
cd /work/longruns
export PYTHONPATH=/work/longruns/code
PY=/work/main/.venv/bin/python
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
