"""Published numbers of the paper's labels (ringcore.paperrefs)."""
import os
from pathlib import Path

import pytest

from ringcore import paperrefs

ROOT = Path(__file__).resolve().parents[2]
CANDIDATES = [Path(os.environ["RINGLAB_PAPER_TEX"])] if os.environ.get("RINGLAB_PAPER_TEX") else []
CANDIDATES += [ROOT.parent / "shared/paper/lehmann_schmidt_salo_2017.tex",
               Path("/work/shared/paper/lehmann_schmidt_salo_2017.tex")]
TEX = next((p for p in CANDIDATES if p.is_file()), None)


@pytest.mark.skipif(TEX is None, reason="the paper's .tex is not on this machine")
def test_shipped_table_equals_derivation_from_tex():
    derived = paperrefs.derive_file(TEX)
    assert derived == paperrefs.NUMBERS
    assert list(derived) == list(paperrefs.NUMBERS)


def test_spot_checks_counted_by_hand():
    """Numbers counted by hand in the .tex (numbered equation environments and align rows in order)."""
    assert paperrefs.eq("nleq") == "Eq. (1)"            # align with one split: one number
    assert paperrefs.eq("coolfunc") == "Eq. (11)"       # 4th row of the align starting at (8)
    assert paperrefs.eq("matni") == "Eq. (17)"
    assert paperrefs.eq("emode") == "Eq. (19a)" and paperrefs.eq("osmode2") == "Eq. (19c)"  # subequations
    assert paperrefs.eq("osfreq") == "Eq. (22)"
    assert paperrefs.eq("halfnodes") == "Eq. (31)"     # after two equation* (not counted)
    assert paperrefs.eq("lambdasigmaap") == "Eq. (56)" and paperrefs.eq("eq:jeans") == "Eq. (57)"
    assert paperrefs.fig("omega") == "Figure 1" and paperrefs.fig("grates") == "Figure 3"  # tables between
    assert paperrefs.fig("lambdap") == "Figure 20" and paperrefs.fig("vgpert") == "Figure 30"  # appendix runs on
    assert paperrefs.tab("scalings") == "Table 1" and paperrefs.tab("tab:nbstat") == "Table 3"
    assert paperrefs.sec("isonosg") == "Section 5.1.1" and paperrefs.sec("strob") == "Appendix A"
    assert paperrefs.sec("boxsize") == "Appendix B.1"


def test_every_label_kind_present():
    kinds = {k.split(":")[0] for k in paperrefs.NUMBERS}
    assert kinds == {"eq", "fig", "tab", "sec"}
    assert sum(k.startswith("fig:") for k in paperrefs.NUMBERS) == 30
    assert sum(k.startswith("tab:") for k in paperrefs.NUMBERS) == 3


def test_unknown_label_is_a_value_error_with_suggestions():
    with pytest.raises(ValueError, match=r"label = 'matn'.*eq:matni"):
        paperrefs.eq("matn")
    with pytest.raises(ValueError, match="figure"):
        paperrefs.fig("matni")


SYNTH = r"""
\section{One}\label{sec:one}
\begin{equation}\label{eq:a} x \end{equation}
\begin{equation*} y \end{equation*}
% \begin{equation}\label{eq:commented} z \end{equation}
50\% of \begin{align}
a &= b \label{eq:r1} \\[0.1cm]
c &= d \nonumber \\
\begin{pmatrix} 1 \\ 2 \end{pmatrix} &= e \label{eq:r3}
\end{align}
\begin{align}\label{eq:split}
\begin{split} a &= b \\ c &= d \end{split}
\end{align}
\subsection{Two}\label{sec:onetwo}
\begin{subequations}\label{eq:sub}
\begin{align} a &= 1 \label{eq:suba} \\ b &= 2 \label{eq:subb} \end{align}
\end{subequations}
\begin{equation} q \tag{*}\label{eq:tagged} \end{equation}
\begin{figure} \caption{F {\bf one} \\ two}\label{fig:f1} \end{figure}
\begin{minipage}{\textwidth}\captionof{table}{T}\label{tab:t1}\end{minipage}
\begin{table} \caption{T2}\label{tab:t2} \end{table}
\begin{figure} \caption{F2}\label{fig:f2} \end{figure}
\section*{Acknowledgments}
\appendix
\section{App}\label{sec:app}
\begin{equation}\label{eq:app1} w \end{equation}
\begin{figure} \caption{F3}\label{fig:f3} \end{figure}
\section{App two}\label{sec:app2}
\begin{equation}\label{eq:app2} w \end{equation}
"""


def test_numbering_rules_on_a_synthetic_source():
    d = paperrefs.derive(SYNTH)
    assert d == {"sec:one": "1", "eq:a": "1", "eq:r1": "2", "eq:r3": "3", "eq:split": "4", "sec:onetwo": "1.1",
                 "eq:sub": "5", "eq:suba": "5a", "eq:subb": "5b", "eq:tagged": "*", "fig:f1": "1", "tab:t1": "1",
                 "tab:t2": "2", "fig:f2": "2", "sec:app": "A", "eq:app1": "A1", "fig:f3": "3", "sec:app2": "B",
                 "eq:app2": "B2"}


def test_format_table_round_trips():
    ns = {}
    exec(paperrefs.format_table(paperrefs.NUMBERS), ns)
    assert ns["NUMBERS"] == paperrefs.NUMBERS


def test_ref_and_html_by_prefix():
    assert paperrefs.ref("eq:matni") == "Eq. (17)" and paperrefs.ref("fig:lambdap") == "Figure 20"
    assert paperrefs.ref("tab:hydropar") == "Table 2" and paperrefs.ref("sec:vgroup") == "Appendix C"
    assert paperrefs.html("eq:osfreq") == '<abbr title="label osfreq">Eq. (22)</abbr>'
    with pytest.raises(ValueError, match="prefixes"):
        paperrefs.ref("matni")
