"""In-process spread of the "Orbits per second" cards of five Hydrodynamics views following one shared run.

    .venv/bin/python scripts/measure_shared_rate_cards.py [SECONDS]   (default 30)

As ``tests/app/test_shared_runs.py`` does, without a browser: five ``HydroView`` pages of identical runs (one
shared computation, runs in this process), paced as in a server session (``served()`` True); two pages acknowledge
every line frame, three only every 1, 2 and 3 s (busy browsers).  After every frame of any page (a common moment,
from 5 s on) the five cards are compared: the spread is (largest - smallest) / median.  Prints the median, the
90th percentile and the largest spread, and the share of moments at which all five cards show the same text.
``scripts/measure_shared_rate_spread.py`` measures the same in real browser pages.
"""
import re
import statistics
import sys
import time

import ringlab.tabs.hydro.view as view_module
from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.server import remote, shared
from ringlab.tabs.hydro.view import HydroView

CARD = re.compile(r'id="hydro-orbits-per-s".*?class="ro-value">([^<]*)<')
remote._BACKEND = None
shared._REGISTRY.clear()
shared.set_enabled(True)
view_module.served = lambda: True
views = []
for _ in range(5):
    r = HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5)); r.running, r.pause_at = True, 1e5
    views.append(HydroView(runner=r))
acked = [0.0] * 5
every = [0, 0, 1.0, 2.0, 3.0]
for i, v in enumerate(views):
    v.image_gate.ready = lambda now: False
    v.line_gate.ready = (lambda now: True) if every[i] == 0 else (lambda now, i=i: now - acked[i] >= every[i])
spreads, same = [], 0
t0 = time.perf_counter()
while time.perf_counter() - t0 < float(sys.argv[1]) if len(sys.argv) > 1 else 30.0:
    for i, v in enumerate(views):
        v.runner.tick()
        if every[i] and v.line_gate.ready(time.perf_counter()):
            acked[i] = time.perf_counter()
        texts = [CARD.search(w.readouts.object).group(1) for w in views]
        if time.perf_counter() - t0 > 5 and all(t != "—" for t in texts):
            vals = [float(t) for t in texts]
            spreads.append((max(vals) - min(vals)) / statistics.median(vals)); same += len(set(texts)) == 1
spreads.sort()
print(f"moments {len(spreads)} median spread {statistics.median(spreads):.3f} p90 {spreads[int(.9*(len(spreads)-1))]:.3f} "
      f"max {spreads[-1]:.3f} all same {same/len(spreads):.3f}")
