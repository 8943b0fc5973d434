"""The "About / Cite" panel: the paper the lab follows, this software, its version and licence, how to cite both.

Everything comes from :mod:`ringcore.citation` (the BibTeX that ``ringcore.cite()`` prints and
``CITATION.cff`` repeats), so the panel, the command line and the citation file name the same paper and
version.  The panel is self-contained (a button that shows or hides it); the page adds it with one line.
Nothing here loads anything from another host: the ADS and arXiv identifiers are text, not links.
"""
from __future__ import annotations

import html
import re

import panel as pn

from ringcore import cite
from ringcore.citation import PAPER_BIBTEX
from ringcore.provenance import __version__, commit

from ringlab.ui.style import CSS

# the article's ADS bibcode, which follows from year, journal, volume, article number and first author; its DOI
# is not in the paper's source we ship and could not be checked offline, so it is not shown (a wrong DOI is worse
# than none): the journal reference, this bibcode and the arXiv number each identify the article
PAPER_ADS = "2017ApJ...851..125L"
LICENSE = "BSD-3-Clause"

ABOUT_CSS = """
.about-box {font-size: 13.5px; line-height: 1.4;}
.about-box h3 {font-size: 15px; margin: 6px 0 2px 0; color: #1f4e79;}
.about-box pre {font-size: 11px; white-space: pre-wrap; background: #f4f6f8; padding: 6px; border-radius: 4px;
                max-height: 260px; overflow: auto; user-select: all;}
"""


def paper_fields() -> dict:
    """Title, journal, year, volume, pages and arXiv number of the paper, read from ringcore's BibTeX."""
    fields = dict(re.findall(r"^\s*(\w+)\s*=\s*\{(.*)\},?\s*$", PAPER_BIBTEX, flags=re.M))
    clean = {k: re.sub(r"[{}]", "", v) for k, v in fields.items()}
    clean["title"] = clean["title"].replace("\\", "")
    return clean


def paper_reference() -> str:
    """One line naming the paper: authors, year, title, journal, volume, article number, ADS bibcode, arXiv."""
    f = paper_fields()
    return (f"Lehmann, M., Schmidt, J. & Salo, H. ({f['year']}). {f['title']}. {f['journal']} {f['volume']}, "
            f"{f['pages']}. ADS: {PAPER_ADS} · arXiv:{f['eprint']}")


def about_html() -> str:
    """The panel's text (HTML)."""
    bib = cite(show=False)
    return (
        '<div class="about-box" id="about-cite">'
        "<h3>The science</h3>"
        "<p>This lab follows one research paper: every equation, figure, table and section number in it is that "
        f"paper's printed number.</p><p id=\"about-paper\"><b>{html.escape(paper_reference())}</b></p>"
        "<h3>This software</h3>"
        f"<p id=\"about-software\">ringlab {html.escape(__version__)} (code version {html.escape(commit()[:12])}): "
        "its numerical core solves the paper's model — the exact linear theory, a one-dimensional hydrodynamic "
        "solver with radial self-gravity and a local N-body simulation — and this web lab shows it. "
        f"Licence: {LICENSE}, an open-source licence.</p>"
        "<h3>How to cite</h3>"
        "<p>If you use results from this lab in a report or paper, cite the paper and the software (these "
        "BibTeX entries are what <i>ringcore.cite()</i> prints in Python):</p>"
        f'<pre id="about-bibtex">{html.escape(bib)}</pre></div>')


# opened: the button and the text under it scrolled to the top of what holds them (the lessons panel, its own scroll
# area as tall as the window, where the text opened below the visible bottom); tried for up to 3 s, while the page
# lays the text out
SHOW_JS = """
if (!cb_obj.active) return;
const find = (root) => { for (const el of root.querySelectorAll('*')) {
    if (el.classList && el.classList.contains('about-cite')) return el;
    if (el.shadowRoot) { const f = find(el.shadowRoot); if (f) return f; } } return null; };
const text = (root) => { for (const el of root.querySelectorAll('*')) {
    if (el.id === 'about-cite') return el;
    if (el.shadowRoot) { const f = text(el.shadowRoot); if (f) return f; } } return null; };
const scroller = (el) => { for (let e = el.parentElement || el.getRootNode().host; e;
    e = e.parentElement || (e.getRootNode() && e.getRootNode().host)) {
  const y = getComputedStyle(e).overflowY;
  if ((y === 'auto' || y === 'scroll') && e.scrollHeight > e.clientHeight + 1) return e; } return null; };
let tries = 0;
const show = () => { const box = find(document), body = text(document);
  if (box && body && body.getBoundingClientRect().height > 0) {
    const panel = scroller(box);  // the panel alone, not the page (the tab beside it stays where it was)
    if (panel) panel.scrollTop += box.getBoundingClientRect().top - panel.getBoundingClientRect().top;
    const r = box.getBoundingClientRect();
    if (r.top < 0 || r.top > innerHeight - 200) box.scrollIntoView({block: 'start'});
    return; }
  if (++tries < 60) setTimeout(show, 50); };
setTimeout(show, 0);
"""


class AboutCite(pn.viewable.Viewer):
    """A button "About / Cite" that shows or hides :func:`about_html` (one per session); opened, the text is
    scrolled into view (:data:`SHOW_JS`)."""

    def __init__(self, **params):
        super().__init__(**params)
        self.button = pn.widgets.Toggle(label="About / Cite", value=False, color="default",
                                        css_classes=["about-toggle"], sizing_mode="stretch_width")
        self.pane = pn.pane.HTML(about_html(), stylesheets=[CSS, ABOUT_CSS], sizing_mode="stretch_width",
                                 visible=False, margin=(0, 5))
        self.button.param.watch(lambda e: setattr(self.pane, "visible", e.new), "value")
        self.button.jslink(self.pane, value="visible")  # shown at once in the page, then scrolled to
        self.button.jscallback(value=SHOW_JS)
        self._layout = pn.Column(self.button, self.pane, sizing_mode="stretch_width", css_classes=["about-cite"])

    def __panel__(self):
        return self._layout
