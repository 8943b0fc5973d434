"""Every plot's save tool names its PNG after the plot (Bokeh's default asks for a name, offering "bokeh_plot")."""
from __future__ import annotations

from bokeh.models import SaveTool

from ringlab.main import create_app
from ringlab.ui.figures import png_name


def test_png_name_is_a_plain_file_name():
    assert png_name("Power spectrum of σ, Eq. (38)") == "ringlab-power-spectrum-of-sigma-eq-38"
    assert png_name("λ_p(t)") == "ringlab-lambda-p-t"
    assert png_name("") == "ringlab-plot"
    assert len(png_name("x" * 200)) <= len("ringlab-") + 60


def test_every_save_tool_of_every_tab_has_a_file_name():
    app = create_app({})
    names = []
    for i in range(len(app.tabs)):
        app.tabs.active = i  # build every tab
    for view in app.views.built():
        model = view.__panel__().get_root()
        for tool in model.select({"type": SaveTool}):
            names.append(tool.filename)
    assert len(names) >= 10, names
    assert all(n and n.startswith("ringlab-") and "bokeh_plot" not in n for n in names), names
