"""The "Linear theory" tab: the dispersion relation and its "Run this in ..." buttons."""
