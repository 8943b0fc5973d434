"""The "Compare" tab: its view and its Bokeh figures."""
