"""Matplotlib figures of the paper's computed results (headless, Agg backend)."""
