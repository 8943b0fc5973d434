"""The documentation site shows a note instead of each live Panel view of a tutorial (no kernel, no CDN)."""
import importlib.util
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[2]


def _ext():
    """The docs extension, imported as Sphinx does it (docs/conf.py puts docs/_ext on sys.path: its modules
    import each other)."""
    ext_dir = str(ROOT / "docs" / "_ext")
    sys.path.insert(0, ext_dir)
    try:
        spec = importlib.util.spec_from_file_location("ringlab_docs", Path(ext_dir) / "ringlab_docs.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
    finally:
        sys.path.remove(ext_dir)
    return mod


def test_panel_outputs_become_notes_and_other_outputs_stay():
    ext = _ext()
    out = nbformat.v4.new_output
    load = out("display_data", data={ext.PANEL_LOAD: "", "application/javascript": "cdn.bokeh.org"})
    style = out("display_data", data={"text/html": "<style>*[data-root-id] {}</style>"})
    view = out("execute_result", data={ext.PANEL_VIEW: "", "text/html": "<script>docs_json</script>",
                                       "text/plain": "Row(...)"}, execution_count=2)
    png = out("display_data", data={"image/png": "iVBOR", "text/plain": "<Figure>"})
    text = out("stream", name="stdout", text="Paused at orbit 3.00\n")
    nb = nbformat.v4.new_notebook(cells=[
        nbformat.v4.new_code_cell("import panel as pn\npn.extension()\nQUICK = True", outputs=[load, style,
                                  out("display_data", data={ext.PANEL_VIEW: "", "text/html": "<div>"})]),
        nbformat.v4.new_code_cell("hydro = HydroView()\nhydro.servable()", outputs=[out("display_data", data={}), view]),
        nbformat.v4.new_code_cell("run.wait()\nprint(orbit)\nplt.plot()", outputs=[text, png]),
    ])
    assert ext.static_views(nb) == 1
    first, second, third = (c.outputs for c in nb.cells)
    assert first == []
    assert len(second) == 1 and "Live view: <code>hydro</code>" in second[0].data["text/html"]
    assert "ringlab tutorials DIR" in second[0].data["text/html"] and "<script" not in second[0].data["text/html"]
    assert third == [text, png]
    nbformat.validate(nb)
