"""The API reference documents the engines' inherited methods (advance, save, keep_archive, load, snapshot ...)
on the Hydro1D and ShearingBox pages, where a researcher looks for them."""
from __future__ import annotations

import pytest

from test_wheel_serve import DOCS_PID, SITE, _wait_for_docs

pytestmark = pytest.mark.skipif(not DOCS_PID and not (SITE / "index.html").is_file(),
                                reason="no documentation site in app/docs_site: run `make docs` first")


@pytest.mark.timeout(2700)
@pytest.mark.parametrize("page, cls", [("ringcore.hydro.solver.Hydro1D.html", "Hydro1D"),
                                       ("ringcore.nbody.box.ShearingBox.html", "ShearingBox")])
def test_engine_pages_list_the_inherited_methods(page, cls):
    if DOCS_PID:
        _wait_for_docs(DOCS_PID)
    found = list(SITE.rglob(page))
    assert found, f"no API page {page} in {SITE}"
    html = found[0].read_text(encoding="utf-8")
    for method in ("advance", "save", "keep_archive", "load", "snapshot", "archive"):
        assert f'id="ringcore.{page[len("ringcore."):-len(".html")]}.{method}"' in html, (cls, method)
