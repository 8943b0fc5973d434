"""Settings and linear-theory helpers of the app (param, no widgets)."""
