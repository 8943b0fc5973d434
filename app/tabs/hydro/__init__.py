"""The "Hydrodynamics" tab: its view and its Bokeh figures."""
