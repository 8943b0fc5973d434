"""The table of ``docs/benchmarks/data/hydro_threads.json`` (``scripts/hydro_threads_record.py``) for the
benchmarks page (a renderer of :mod:`ringlab_docs`)."""
from __future__ import annotations


def hydro_thread_tables(d: dict) -> str:
    """Markdown of ``scripts/hydro_threads_record.py --record``: the parts of a step, a region's entry, the
    2-thread speed-up per grid size."""
    from ringlab_docs import _fmt, _table

    pr = d.get("profile_4000") or {}
    text = (f"Recorded {d.get('recorded', '?')} with `python scripts/hydro_threads_record.py"
            f"{' --rt' if d.get('rt') else ''}` on {_fmt(d.get('cores', '?'))} cores, load average "
            f"{_fmt(d.get('load_before', '?'))} before and {_fmt(d.get('load_after', '?'))} after"
            f"{' (timed bursts at real-time priority, duty cycle under 10 %)' if d.get('rt') else ''}.\n\n"
            "Where a one-thread step of 4,000 cells goes (µs, best of many calls; a step is five stages of "
            "FFT + fluxes + sources + update, the first stage with the maxima, then the check):\n\n")
    names = [("step", "whole step"), ("fft", "FFT self-gravity"), ("fluxes", "fluxes (primitives, splitting, MP5, "
             "derivatives)"), ("maxima_extra", "grid maxima (first stage)"), ("sources", "flux difference and sources"),
             ("update", "stage update"), ("check", "state check")]
    text += _table([dict(part=label, us=pr.get(k, "?")) for k, label in names], [("part", "part"), ("us", "µs")])
    sy = d.get("sync") or {}
    text += (f"\nEntering an empty parallel region of 2 threads: {_fmt(sy.get('region_back_to_back_min_us', '?'))} µs "
             f"back to back (median {_fmt(sy.get('region_back_to_back_median_us', '?'))}), "
             f"{_fmt(sy.get('region_after_300us_min_us', '?'))} µs after 300 µs of other work (median "
             f"{_fmt(sy.get('region_after_300us_median_us', '?'))}). Windows from {_fmt(d.get('min_nodes_per_window', '?'))}"
             f" cells each, FFT share {_fmt(d.get('fft_share', '?'))}, {_fmt(d.get('spins', '?'))} spin checks "
             "before a wait sleeps.\n\nWall time per step, best burst (below the default's threshold the 2 windows "
             "are forced):\n\n")
    text += _table(d.get("scaling", []), [("cells", "cells"), ("one_us", "1 thread [µs]"), ("two_us", "2 threads [µs]"),
                                          ("speedup", "speed-up"), ("windows_forced", "windows forced"),
                                          ("same_bits", "same bits")])
    return text
