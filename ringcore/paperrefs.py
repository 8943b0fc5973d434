"""Published equation, figure, table and section numbers of Lehmann, Schmidt & Salo (2017).

The code, docstrings and app cite the paper by its LaTeX labels (``eq. (matni)``, ``Figure "lambdap"``);
a student holding the published article needs the printed numbers.  :data:`NUMBERS` maps every label of
the paper to its number, derived by :func:`derive` from the order of the numbered environments in the
paper's ``.tex`` (the ``.tex`` is not shipped with the package, so the derived table is kept here as data;
``tests/core/test_paperrefs.py`` re-derives it from the ``.tex`` when that file exists and compares).

Numbering rules (LaTeX + amsmath + the AASTeX 6.2 class the paper uses, ``aastex62.cls``):

- ``equation``: one number; ``equation*`` none.  ``align`` / ``eqnarray`` / ``gather`` / ``flalign``: one
  number per row (rows end at ``\\\\`` outside inner ``split`` / ``aligned`` / matrices / arrays), except rows
  with ``\\nonumber`` / ``\\notag``; the starred forms none.  ``multline``: one number.  ``\\tag{x}`` prints x.
- ``subequations``: one main number N (a label right after ``\\begin{subequations}`` gets N); the equations
  inside are Na, Nb, ...
- Figures / tables: one number per ``\\caption`` (or ``\\captionof{figure|table}``), never reset (the class
  keeps figure and table numbers running through the appendix).
- Sections: 1, 1.1, 1.1.1 (``secnumdepth`` 3); ``\\section*`` none.  ``\\appendix`` letters the sections
  (A, B, ...), resets the equation counter and prints appendix equations as A1, A2, ... (the counter is
  not reset per appendix section, as in the class).  The paper has no equations in its appendices.
- ``\\label`` takes the number of the last numbered item before it (in an ``align`` row: that row's number).

>>> eq("matni"), fig("lambdap"), tab("hydropar")
('Eq. (17)', 'Figure 20', 'Table 2')
"""
from __future__ import annotations

import difflib
import re
import string
from pathlib import Path

_ROWS = {"align", "eqnarray", "gather", "flalign", "alignat", "xalignat"}
_SINGLE = {"equation", "multline"}
_INNER = {"split", "aligned", "alignedat", "gathered", "array", "matrix", "pmatrix", "bmatrix", "Bmatrix",
          "vmatrix", "Vmatrix", "smallmatrix", "cases", "subarray", "tabular", "substack"}
_TOKEN = re.compile(r"\\\\|\\begin\{([^}]*)\}|\\end\{([^}]*)\}|\\label\{([^}]*)\}|\\(nonumber|notag)\b"
                    r"|\\tag\*?\{([^}]*)\}|\\appendix\b|\\((?:sub){0,2})section(\*?)\s*(?:\[[^\]]*\])?\{"
                    r"|\\captionof\{(figure|table)\}|\\caption\b")


def _strip_comments(tex: str) -> str:
    return "\n".join(re.sub(r"(?<!\\)%.*", "", line) for line in tex.splitlines())


def derive(tex: str) -> dict:
    """Number of every ``\\label`` in a LaTeX source, by the rules of the module docstring.

    Parameters
    ----------
    tex : str
        LaTeX source text.

    Returns
    -------
    dict
        ``{label: number}``, numbers as printed (``"12"``, ``"5b"``, ``"A1"``, ``"4.2"``), in source order.
    """
    tex = _strip_comments(tex)
    out: dict = {}
    eqn, fign, tabn = 0, 0, 0
    secs = [0, 0, 0]
    appendix = False
    current = ""
    sub = None                      # [main number, letters used] inside subequations
    stack: list = []                # open environments
    row = None                      # current align row: {"labels": [], "skip": bool, "tag": str|None}
    single = None                   # current equation env: {"labels": [], "tag": str|None}

    def eq_number() -> str:
        nonlocal eqn
        if sub is not None:
            sub[1] += 1
            return f"{sub[0]}{string.ascii_lowercase[sub[1] - 1]}"
        eqn += 1
        return f"{string.ascii_uppercase[secs[0] - 1]}{eqn}" if appendix else str(eqn)

    def close_row():
        nonlocal current, row
        if row is None:
            return
        if not row["skip"] or row["tag"]:
            current = row["tag"] or eq_number()
            for lab in row["labels"]:
                out[lab] = current
        row = None

    def in_rows() -> bool:
        return bool(stack) and stack[-1] in _ROWS

    for m in _TOKEN.finditer(tex):
        tok = m.group(0)
        if tok == "\\\\":
            if in_rows():
                close_row()
                row = dict(labels=[], skip=False, tag=None)
        elif m.group(1) is not None:                      # \begin{env}
            env = m.group(1).strip()
            base = env.rstrip("*")
            if env == "subequations":
                eqn += 1
                current = f"{string.ascii_uppercase[secs[0] - 1]}{eqn}" if appendix else str(eqn)
                sub = [current, 0]
            elif base in _ROWS and not env.endswith("*"):
                row = dict(labels=[], skip=False, tag=None)
            elif base in _SINGLE and not env.endswith("*"):
                single = dict(labels=[], tag=None)
            stack.append(env)
        elif m.group(2) is not None:                      # \end{env}
            env = m.group(2).strip()
            if env == "subequations":
                sub = None
            elif env in _ROWS:
                close_row()
            elif env in _SINGLE and single is not None:
                current = single["tag"] or eq_number()
                for lab in single["labels"]:
                    out[lab] = current
                single = None
            if stack and stack[-1] == env:
                stack.pop()
        elif m.group(3) is not None:                      # \label
            lab = m.group(3).strip()
            if row is not None and (in_rows() or (stack and stack[-1] in _INNER)):
                row["labels"].append(lab)
            elif single is not None:
                single["labels"].append(lab)
            else:
                out[lab] = current
        elif m.group(4) is not None:                      # \nonumber, \notag
            if row is not None:
                row["skip"] = True
        elif m.group(5) is not None:                      # \tag{x}
            if row is not None:
                row["tag"] = m.group(5)
            elif single is not None:
                single["tag"] = m.group(5)
        elif tok == "\\appendix":
            appendix, eqn, secs = True, 0, [0, 0, 0]
        elif m.group(6) is not None:                      # \section, \subsection, \subsubsection
            if m.group(7):
                continue
            level = len(m.group(6)) // 3
            secs[level] += 1
            secs[level + 1:] = [0] * (2 - level)
            head = string.ascii_uppercase[secs[0] - 1] if appendix else str(secs[0])
            current = ".".join([head] + [str(s) for s in secs[1:level + 1]])
        else:                                             # \caption, \captionof{...}
            kind = m.group(8) or next((e.rstrip("*") for e in reversed(stack)
                                       if e.rstrip("*") in ("figure", "table")), "figure")
            if kind == "table":
                tabn += 1
                current = str(tabn)
            else:
                fign += 1
                current = str(fign)
    return out


def derive_file(path) -> dict:
    """:func:`derive` applied to a ``.tex`` file (UTF-8)."""
    return derive(Path(path).read_text(encoding="utf-8"))


def format_table(numbers: dict) -> str:
    """The ``NUMBERS`` literal of this module for ``numbers`` (used to regenerate it)."""
    items = [f"{k!r}: {v!r}" for k, v in numbers.items()]
    lines, line = [], "NUMBERS = {"
    for it in items:
        if len(line) + len(it) + 2 > 114:
            lines.append(line.rstrip())
            line = "    "
        line += it + ", "
    lines.append(line.rstrip().rstrip(",") + "}")
    return "\n".join(lines)


# Generated by `python -m ringcore.paperrefs /work/shared/paper/lehmann_schmidt_salo_2017.tex`.
NUMBERS = {'sec:intro': '1', 'sec:theo': '2', 'eq:nleq': '1', 'eq:poissoneq': '2', 'eq:temp': '3',
    'eq:ploc': '4', 'eq:heatflux': '5', 'eq:pten': '6', 'eq:du': '7', 'eq:pres': '8', 'eq:shearvis': '9',
    'eq:heatcon': '10', 'eq:coolfunc': '11', 'eq:ptot': '12', 'eq:linper': '14', 'eq:wkbsg': '15',
    'eq:evp': '16', 'eq:matni': '17', 'eq:emode': '19a', 'eq:osmode1': '19b', 'eq:osmode2': '19c',
    'eq:ideal': '20', 'eq:osgrate': '21', 'eq:osfreq': '22', 'eq:vg': '23', 'fig:omega': '1', 'fig:vgroup': '2',
    'sec:hydropar': '3', 'tab:scalings': '1', 'tab:hydropar': '2', 'sec:numerics': '4', 'sec:hydro': '4.1',
    'eq:convar': '24', 'eq:energy': '25', 'eq:hcl': '26', 'eq:physflux': '27', 'eq:defnumflux': '28',
    'eq:numflux': '29', 'eq:halfnodes': '31', 'eq:timestep': '32', 'eq:jacobian': '33', 'eq:evalni': '34',
    'eq:evali': '35', 'eq:fvs1': '36', 'eq:fvs2': '37', 'eq:fourier': '38', 'eq:ekin': '39',
    'sec:hydronumsg': '4.1.2', 'eq:sgint': '41', 'eq:sgsum': '42', 'eq:cbin': '43', 'eq:conv': '44',
    'eq:kernel': '45', 'eq:convol': '46', 'eq:backconvol': '47', 'sec:hydronumtests': '4.1.3', 'fig:grates': '3',
    'sec:nbsim': '4.2', 'eq:bridges': '48', 'eq:hill': '49', 'tab:nbstat': '3', 'sec:nbsg': '4.2.1',
    'eq:wtfac': '51', 'eq:fdecomp': '52', 'eq:sgmodes': '54', 'sec:nbtest': '4.2.2', 'fig:nblin1': '4',
    'fig:nblin2': '5', 'sec:results': '5', 'sec:hydronosg': '5.1', 'sec:isonosg': '5.1.1', 'fig:tau15ngb': '6',
    'fig:tau15nga': '7', 'fig:ekinisonosg': '8', 'fig:tau15bufnosg': '9', 'sec:nonisonosg': '5.1.2',
    'fig:tau20nonisonosgb': '10', 'fig:tau20nonisonosga': '11', 'sec:hydrosg': '5.2', 'sec:isosg': '5.2.1',
    'fig:ekincompare': '12', 'fig:sgstable': '13', 'sec:nonisosg': '5.2.2', 'fig:etauhydro': '14',
    'fig:tau15nonisoweaksg': '15', 'sec:nbres': '5.3', 'fig:fluctnb': '16', 'fig:enbody': '17',
    'fig:boxdouble': '18', 'fig:vdispnb': '19', 'sec:lambdasat': '6', 'fig:lambdap': '20',
    'eq:lambdasigma': '55', 'sec:nldisp': '6.1', 'fig:nlvg': '21', 'fig:nbvga': '22', 'fig:nbvgc': '23',
    'sec:per': '6.2', 'fig:nlvgbuff': '24', 'fig:osfrat': '25', 'sec:radius': '6.3', 'eq:lambdasigmaap': '56',
    'eq:jeans': '57', 'fig:radvar': '26', 'sec:comp': '6.4', 'sec:conc': '7', 'sec:strob': 'A', 'fig:vgph': '27',
    'sec:boxsize': 'B.1', 'fig:boxsizecomp01': '28', 'sec:pmod': 'B.2', 'sec:altsat': 'B.3',
    'fig:sig500buff': '29', 'sec:vgroup': 'C', 'fig:vgpert': '30'}


def number(label: str, prefix: str = "eq") -> str:
    """Published number of ``label`` (with or without the ``prefix:``), e.g. ``number("matni") -> "30"``.

    Raises ValueError naming the label and the closest known labels if it is not in the paper.
    """
    key = label if ":" in label else f"{prefix}:{label}"
    if key not in NUMBERS:
        near = difflib.get_close_matches(key, list(NUMBERS), n=4)
        kind = {"eq": "an equation", "fig": "a figure", "tab": "a table", "sec": "a section"}.get(prefix, prefix)
        raise ValueError(f"label = {label!r} is not {kind} label of the paper: allowed are the paper's \\label "
                         f"names" + (f" (closest: {', '.join(near)})" if near else ""))
    return NUMBERS[key]


def eq(label: str) -> str:
    """Printed citation of an equation label.

    ``"matni"`` or ``"eq:matni"`` gives ``"Eq. (17)"``: ``"Eq. (N)"`` with the published number N.
    """
    return f"Eq. ({number(label, 'eq')})"


def fig(label: str) -> str:
    """``"Figure N"`` for a figure label (``"lambdap"`` or ``"fig:lambdap"``)."""
    return f"Figure {number(label, 'fig')}"


def tab(label: str) -> str:
    """``"Table N"`` for a table label (``"hydropar"`` or ``"tab:hydropar"``)."""
    return f"Table {number(label, 'tab')}"


def sec(label: str) -> str:
    """``"Section N"`` (or ``"Appendix A"``) for a section label (``"isonosg"`` or ``"sec:isonosg"``)."""
    n = number(label, "sec")
    return f"Appendix {n}" if n[:1].isalpha() else f"Section {n}"


def ref(label: str) -> str:
    """Printed reference for a full label.

    ``"eq:matni" -> "Eq. (17)"``, ``"fig:lambdap" -> "Figure 20"``,
    ``"tab:hydropar" -> "Table 2"``, ``"sec:isonosg" -> "Section 5.1.1"``."""
    kind = label.split(":", 1)[0] if ":" in label else ""
    funcs = {"eq": eq, "fig": fig, "tab": tab, "sec": sec}
    if kind not in funcs:
        raise ValueError(f"label = {label!r} is not valid: allowed a label with one of the prefixes eq:, fig:, "
                         f"tab:, sec:")
    return funcs[kind](label)


def html(label: str) -> str:
    """:func:`ref` of ``label`` as HTML, with the LaTeX label as tooltip.

    ``"eq:matni"`` gives ``<abbr title="label matni">Eq. (17)</abbr>``.
    """
    return f'<abbr title="label {label.split(":", 1)[1]}">{ref(label)}</abbr>'


if __name__ == "__main__":  # pragma: no cover - regenerate NUMBERS
    import sys

    print(format_table(derive_file(sys.argv[1] if len(sys.argv) > 1
                                   else "/work/shared/paper/lehmann_schmidt_salo_2017.tex")))
