"""Live runs without widgets: runners, their loop, plot buffers, run keeper, export checks, the session."""
