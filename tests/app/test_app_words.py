"""Every word a student reads: published numbers (never the paper's LaTeX labels), no internal jargon, no
files or commands a student cannot see, units once.

Builds the app headless and walks every tab and every lesson step (panes, widget names, tooltips, options,
tab titles, Bokeh titles, axis and legend labels, hover tooltips), the glossary, the check messages as the
Lessons panel shows them, the worksheets and the tutorials' sources.
"""
import html
import re
from pathlib import Path

import panel as pn
import pytest
from bokeh.models import Axis, Div, HoverTool, LegendItem, Plot, Title

from ringlab.lessons.checks import Result
from ringlab.lessons.content import LESSONS
from ringlab.lessons.glossary import glossary_html
from ringlab.paths import TUTORIALS_SRC_DIR, WORKSHEETS_DIR
from ringlab.ui.cite import publish, raw_labels

# words a student cannot act on: internal names, abbreviations, files and commands of the source tree
JARGON = re.compile(r"CFL|f_t from|mOrb|nothing reset|Settings invalid|answer = None|README"
                    r"|<code>(?:ringcore|make|ringlab)\b|`ringcore |ringcore\.(?!cite\(\))\w|tutorials/\w|paper label"
                    r"|\(metres\)|\(mm/s\)|\(10⁻³ m²/s\)")


def texts(obj, seen):
    """Every string a student can read (or hover) in a Panel/Bokeh object tree."""
    if id(obj) in seen:
        return
    seen.add(id(obj))
    if isinstance(obj, pn.viewable.Viewer):
        yield from texts(obj.__panel__(), seen)
        return
    if isinstance(obj, pn.pane.PaneBase) and isinstance(getattr(obj, "object", None), str):
        yield obj.object
    if isinstance(obj, pn.widgets.Widget):
        for attr in ("name", "description", "placeholder"):
            value = getattr(obj, attr, None)
            if isinstance(value, str) and value:
                yield value
        options = getattr(obj, "options", None)
        if isinstance(options, (dict, list)):
            yield from (str(o) for o in options)
    if isinstance(obj, pn.Tabs):
        yield from (str(n) for n in obj._names)
    if isinstance(obj, pn.Card):
        yield str(obj.title)
    fig = obj.object if isinstance(obj, pn.pane.Bokeh) else obj if isinstance(obj, Plot) else None
    if fig is not None:
        for m in fig.references():
            if isinstance(m, Title):
                yield str(m.text)
            elif isinstance(m, Axis) and m.axis_label:
                yield str(m.axis_label)
            elif isinstance(m, LegendItem) and m.label is not None:
                lab = m.label
                yield str(lab.get("value", "") if isinstance(lab, dict) else getattr(lab, "value", lab))
            elif isinstance(m, HoverTool):
                yield str(m.tooltips)
            elif isinstance(m, Div):
                yield str(m.text)
    for child in getattr(obj, "objects", []) or []:
        yield from texts(child, seen)


def problems(where: str, text: str) -> list:
    # a link's address is not read (the docs site's tutorial pages live under docs/tutorials/nb/ once built)
    text = re.sub(r'href="[^"]*"', 'href=""', text)
    found = [f"{where}: label {r!r}" for r in raw_labels(text)]
    found += [f"{where}: jargon {m.group(0)!r} in {text[max(0, m.start() - 60):m.end() + 40]!r}"
              for m in JARGON.finditer(text)]
    return found


def test_publish_writes_every_form_of_label_as_its_published_number():
    cases = {'e_kin, eq. (ekin)': "e_kin, eq. (39)", "Figure 'tau15bufnosg'": "Figure 9",
             'Figure "lambdap"': "Figure 20", 'Appendix Section "strob"': "Appendix A",
             'Appendix "Stroboscopic Space-Time Diagram"': "Appendix A", 'Section\n"Numerical Methods"': "Section 4",
             "Table 'Hydrodynamic Parameters'": "Table 2", 'Table "Hydrodynamic Parameters"': "Table 2",
             "[[sec:per]], [[fig:lambdap]], [[osgrate]]": "Section 6.2, Figure 20, Eq. (21)",
             "(eq. timestep, f_t = 0.1)": "(Eq. (32), f_t = 0.1)",
             "caption of Figure 8 ('ekinisonosg')": "caption of Figure 8"}
    for raw, shown in cases.items():
        assert raw_labels(raw), raw  # the detector sees the label ...
        assert publish(raw, html_out=False) == shown
        assert raw_labels(publish(raw)) == []  # ... and nothing of it is left, tooltip included
    out = publish("eq. (ekin)")
    assert 'title="in Lehmann, Schmidt &amp; Salo (2017), ApJ 851, 125"' in out and "ekin" not in out
    assert raw_labels("eq. (16), Figure 20, Appendix A, Table 2, eqs. (8)-(11)") == []


@pytest.mark.timeout(600)
def test_no_tab_or_lesson_step_shows_a_label_or_jargon():
    from ringlab.main import TABS, create_app

    app = create_app()
    bad, seen = [], []
    for (title, _), view in zip(TABS, app.views):
        for text in texts(view, set()):
            seen.append(text)
            bad += problems(title, text)
    for text in texts(app, set()):  # the page around the tabs: header, side column, About / Cite
        seen.append(text)
        bad += problems("page", text)
    panel = app.lessons
    for les in LESSONS:
        for step in range(1, len(les.steps) + 1):
            panel.param.update(lesson=les.number, step=step)
            for text in texts(panel, set()):
                seen.append(text)
                bad += problems(f"lesson {les.number} step {step}", text)
    assert not bad, "\n".join(sorted(set(bad))[:40])
    # the walk reaches explanations, tooltips, options, legends and every step (else it could not fail)
    joined = "\n".join(seen)
    for must in ("Wave kinetic energy e_kin, Eq. (39)", 'title="in Lehmann, Schmidt', "Row of Table 2",
                 "fast (about 10 times larger steps)", "Appendix A", "fastest-growing λ (linear)", "About / Cite",
                 "ADS: 2017ApJ...851..125L",
                 LESSONS[-1].steps[-1].title):
        assert must in joined, must


def test_check_messages_reach_the_student_with_published_numbers(monkeypatch):
    """A check's message (written with labels in ringlab.lessons.checks) is shown through publish()."""
    from ringlab.lessons import view as lessons_view
    from ringlab.lessons.view import LessonsPanel

    message = ("one source and one sink, as in Figure 'tau15bufnosg'; the paper's relation, eq. (lambdasigma); "
               'the growth rate is negative there, eq. (osgrate); stroboscopic (Appendix Section "strob")')
    monkeypatch.setattr(lessons_view, "run_check", lambda *a, **k: Result("wrong", message))
    panel = LessonsPanel()
    panel.check()
    shown = panel.feedback.object
    assert problems("feedback", shown) == []
    plain = re.sub(r"<[^>]+>", "", shown)
    assert "Figure 9" in plain and "eq. (55)" in plain and "eq. (21)" in plain and "(Appendix A)" in plain


def test_check_sources_cite_only_labels_of_the_paper():
    """Every label a check message cites is a label of the paper (publish leaves unknown ones as they are)."""
    import ringlab.lessons.checks as checks

    source = Path(checks.__file__).read_text(encoding="utf-8")
    # an f-string's {paperrefs.sec('label')} prints the published number when it runs: not a raw citation
    strings = [s for s in re.findall(r'"([^"\n]*)"', source) if "{paperrefs." not in s]
    left = [s for s in strings if raw_labels(publish(s, html_out=False))]
    assert not left, left


def test_glossary_worksheets_and_tutorials_cite_published_numbers():
    bad = problems("glossary", glossary_html())
    sheets = sorted(WORKSHEETS_DIR.glob("lesson*.html"))
    assert len(sheets) == len(LESSONS)
    for f in sheets:
        bad += problems(f.name, html.unescape(f.read_text(encoding="utf-8")))
    tutorials = sorted(Path(TUTORIALS_SRC_DIR).glob("[0-9][0-9]_*.py"))
    assert len(tutorials) >= 5
    for f in tutorials:
        # the markdown of a jupytext source is in comments; a citation may break across two comment lines
        source = f.read_text(encoding="utf-8")
        text = re.sub(r"(?m)^\s*# ?", "", source)
        prose = "\n".join(re.findall(r"(?m)^\s*# ?(.*)$", source))  # a quoted "bridges" in code is a setting
        bad += [f"{f.name}: label {r!r}" for r in raw_labels(text, quoted=False) + raw_labels(prose)]
        bad += [f"{f.name}: tooltip with a LaTeX label" for _ in re.finditer(r'title="label ', text)]
        bad += [f"{f.name}: {m.group(0)!r}" for m in re.finditer(r"\bREADME\b", text)]
    assert not bad, "\n".join(bad[:40])


def test_units_are_given_once_in_questions():
    """The answer box shows the unit ([m]); the question text does not repeat it in words."""
    for les in LESSONS:
        for st in les.steps:
            q = st.question
            if q.unit:
                assert f"({q.unit})" not in q.text and "(metres)" not in q.text, q.text
                assert f"in units of {q.unit}" not in q.text, q.text


def test_glossary_has_the_words_of_the_lessons():
    from ringlab.lessons.glossary import TERMS

    need = {"overstability": ("oscillat", "grows", "β_c"), "lambda_p": ("PSD", "1.4 λ_zero"),
            "PSD": ("Fourier", "wavelength"), "source_sink": ("source", "sink", "stroboscopic"),
            "group_velocity": ("dω_I/dk", "energy", "λ_zero"), "shearing_box": ("shear", "N-body", "edge")}
    for key, words in need.items():
        term = TERMS[key]
        assert all(w in term.text for w in words), (key, term.text)
        assert term.refs and len(term.text) < 600  # short, with the paper's published numbers
        page = glossary_html([key])
        assert raw_labels(page) == [] and re.search(r"(Eq\.|Figure|Section|Appendix) [(A-Z0-9]", page), page
    for les in LESSONS:  # every word a lesson tells the student to look up is in the glossary
        assert set(les.terms) <= set(TERMS), les.terms
    assert glossary_html(query="power spectral").count("<dt") == 1
    assert glossary_html(query="shearing").count("<dt") >= 1


def test_a_choice_question_without_a_choice_says_so_in_words():
    from ringlab.lessons.checks import _choice

    res = _choice(None, ("sources", "sinks"), 0, "why")
    assert res.status == "error" and "None" not in res.message and "answer =" not in res.message
    assert "sources or sinks" in res.message


def test_about_cite_names_the_paper_and_this_software():
    import ringcore
    from ringlab.main import create_app
    from ringlab.ui.about import PAPER_ADS, AboutCite, about_html, paper_fields

    text = html.unescape(re.sub(r"<[^>]+>", " ", about_html()))
    for words in ("Lehmann, M., Schmidt, J. & Salo, H. (2017)", "Viscous Overstability in Saturn's Rings",
                  "The Astrophysical Journal 851, 125", f"ADS: {PAPER_ADS}", "arXiv:1804.07968",
                  f"ringlab {ringcore.__version__}", "BSD-3-Clause", "ringcore.cite()"):
        assert words in text, words
    assert ringcore.cite(show=False).strip() in text  # the same BibTeX the core prints
    f = paper_fields()  # the bibcode is the one ADS builds from year, journal, volume, article and first author
    assert PAPER_ADS == f"{f['year']}ApJ..{f['volume']:.>4}.{f['pages']:.>4}{f['author'].strip()[0]}"
    assert problems("about", about_html()) == []
    # the paper named in the panel is the one of CITATION.cff (read from the source tree when it is there)
    cff = Path(ringcore.__file__).resolve().parent.parent / "CITATION.cff"
    if cff.exists():
        meta = cff.read_text(encoding="utf-8")
        f = paper_fields()
        assert f"volume: {f['volume']}" in meta and f"start: {f['pages']}" in meta and f["eprint"] in meta
        assert "license: BSD-3-Clause" in meta
    # on the page: a button in the side column that shows the panel
    app = create_app()
    about = [o for o in app.select(AboutCite)] or [v for v in app.select(pn.widgets.Toggle) if v.name == "About / Cite"]
    assert about, "no About / Cite on the page"
    widget = AboutCite()
    assert not widget.pane.visible
    widget.button.value = True
    assert widget.pane.visible and "about-bibtex" in widget.pane.object


def _numbers(text: str) -> list:
    return [float(x) for x in re.findall(r"(?<![\w.])\d+(?:\.\d+)?(?:e-?\d+)?", text.replace("−", "-"))]


def test_no_step_gives_the_number_it_asks_for():
    """Neither a step's texts nor its hint state (within the check's tolerance) the number the step asks for;
    the tenfold time of lesson 1 step 2 is not on any card of the Linear tab, and the e_kin legend of lesson 2
    step 1 names the linear wave but not its growth rate (tests/app/test_connect.py)."""
    import math

    from ringcore import linear, params
    from ringlab.lessons.checks import linear_values
    from ringlab.lessons.presets import apply_preset
    from ringlab.lessons.view import LessonsPanel
    from ringlab.main import create_app

    app = create_app()
    panel: LessonsPanel = app.lessons
    linear_view = app.views[0]
    for les in LESSONS:
        for k, st in enumerate(les.steps, start=1):
            q = st.question
            said = _numbers(" ".join((st.predict, st.look_for, q.text, q.hint)))
            truth = None
            if q.check == "linear_number":
                apply_preset(st.preset, panel.targets(), "fast")
                truth = linear_values(panel.targets().linear)[q.args["key"]]
                tol = max(q.args.get("rel_tol", 0) * abs(truth), q.args.get("abs_tol", 0))
            elif q.check == "hydro_growth_rate":  # a copied linear rate would pass the check: not in the text
                truth = linear.summary(params.get("tau15", 0.0).isothermal_limit(1.0)).max_growth_rate
                tol = 0.5 * truth
            if truth is None:
                continue
            near = [x for x in said if abs(x - truth) <= tol]
            assert not near, f"lesson {les.number} step {k} states {near} next to its question (answer {truth:.4g})"
            if q.args.get("key") in ("tenfold_orbits", "efold_orbits"):
                cards = " ".join(t for t in texts(linear_view, set()) if "linear-readouts" in t)
                assert "ro-max-growth" in cards and linear_view.controls.sigma0 == 400.0  # the step's preset
                shown = _numbers(re.sub(r"<[^>]+>", " ", cards))
                assert not [x for x in shown if abs(x - truth) <= tol], (truth, shown)
                assert math.isfinite(truth) and truth > 0
