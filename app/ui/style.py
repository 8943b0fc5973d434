"""The app's CSS: readout cards, keys, messages (``BASE_CSS``: the Linear tab; ``CSS``: every tab)."""
from __future__ import annotations

from ringlab.ui.present import scalable

BASE_CSS = """
.readouts {display: grid; grid-template-columns: repeat(auto-fill, minmax(150px, 1fr)); gap: 8px;
           font-family: var(--bokeh-base-font, sans-serif);}
.readout {border: 1px solid #d0d7de; border-radius: 6px; padding: 6px 10px; background: #f8fafc;}
.ro-label {font-size: 13px; color: #444;}
.ro-value {font-size: 22px; font-weight: 600; color: #111;}
.ro-note {font-size: 12px; color: #555;}
.key {display: flex; flex-wrap: wrap; gap: 4px 18px; font-size: 14px; margin: 4px 0 2px 0; align-items: center;}
.key-item {display: inline-flex; align-items: center; gap: 6px;}
.key-line {display: inline-block; width: 30px; height: 0; border-top-style: solid;}
.key-vline {display: inline-block; width: 0; height: 16px; border-left-style: dashed; border-left-width: 2px;}
.model-label {font-size: 16px; color: #222; margin-bottom: 4px; font-weight: 600;}
.msg-ok {border: 1px solid #2e7d32; background: #edf7ee; color: #1b4d20; border-radius: 6px; padding: 6px 10px;
         font-size: 14px;}
.msg-error {border: 2px solid #b00020; background: #fdecee; color: #7a0014; border-radius: 6px;
            padding: 8px 10px; font-size: 14px;}
.msg-warn {border: 1px solid #b26a00; background: #fff6e5; color: #5c3700; border-radius: 6px; padding: 6px 10px;
           font-size: 14px;}
"""

CSS = BASE_CSS + """
.buttons-note {font-size: 13px; color: #444;}
.status {font-size: 15px; color: #1f4e79; font-weight: 600; padding: 2px 0;}
.msg-ok {border: 1px solid #2e7d32; background: #edf7ee; color: #1b4d20; border-radius: 6px; padding: 6px 10px;
         font-size: 14px;}
.msg-warn {border: 1px solid #b26a00; background: #fff6e5; color: #5c3700; border-radius: 6px; padding: 6px 10px;
           font-size: 14px;}
.group-title {font-weight: 600; font-size: 15px; margin: 10px 0 0 0; color: #1f4e79;}
"""

# every font size follows the page's text scale (presentation mode, ringlab.ui.present)
BASE_CSS, CSS = scalable(BASE_CSS), scalable(CSS)
EXPLANATION_FONT = "calc(15px * var(--rl-scale, 1))"  # the tabs' "What am I looking at?" text
