"""The app's one palette: colours of the wavelength markers and lines, the same in every tab."""
from __future__ import annotations

ZERO_COLOR = "#c2185b"  # lambda_zero
MAXG_COLOR = "#ef6c00"  # fastest-growing wavelength
EMP_COLOR = "#1565c0"  # 1.4 lambda_zero, Eq. (55)
LP_COLOR = "#2e7d32"  # measured lambda_p
BUFFER_COLOR = "#9c27b0"
LINE_COLOR = "#1f4e79"
CURRENT_COLOR = "#111111"  # the current setting's curve (Linear tab)
