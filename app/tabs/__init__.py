"""The tabs of the lab: one module or folder per tab, each with its plots (imports lessons, live, model, ui, server)."""
