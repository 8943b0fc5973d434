"""``from ringlab import HydroView, ...``: the live views for notebooks, and the offline resources in a kernel."""
import subprocess
import sys


def test_views_import_from_the_package_and_are_the_tabs():
    import ringlab
    from ringlab import HydroView, LinearView, NBodyView, PaperView
    from ringlab.tabs.hydro.view import HydroView as Tab

    assert HydroView is Tab
    assert {c.__name__ for c in (HydroView, LinearView, NBodyView, PaperView)} == set(ringlab.__all__)
    try:
        ringlab.NoSuchView
    except AttributeError as e:
        assert "NoSuchView" in str(e)
    else:
        raise AssertionError("an unknown name must raise AttributeError")


def test_import_ringlab_stays_light():
    code = "import sys, ringlab; print('panel' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


def test_installed_resources_only_in_a_jupyter_kernel(monkeypatch):
    import panel as pn

    from ringlab import views

    monkeypatch.setattr(pn.config, "inline", False)
    assert not views.in_jupyter_kernel() and not views.use_installed_resources()
    assert pn.config.inline is False  # a script or `panel serve` keeps its resources

    class Shell:
        kernel = object()

    import IPython

    monkeypatch.setattr(IPython, "get_ipython", lambda: Shell())
    from ringlab.ui import tab

    monkeypatch.setattr(tab, "ON_DISPLAY", [])  # process-wide: dropped after
    assert views.in_jupyter_kernel() and views.use_installed_resources() and views.use_installed_resources()
    assert pn.config.inline is True  # pn.extension() now loads BokehJS and Panel from the installed packages
    assert tab.ON_DISPLAY == [views.serve_panel_stylesheets]  # a view's output names Panel's stylesheets on the
    # Jupyter server once displayed (once, however often it is called)
