"""What to cite when ringcore contributed to a result: the paper whose model it implements and the software.

Like REBOUND's ``sim.cite()``: :func:`cite` prints the references as BibTeX and returns the text; the same
references are in ``CITATION.cff`` at the top of the repository.
"""
from __future__ import annotations

from .provenance import __version__, commit

PAPER_BIBTEX = r"""@article{Lehmann2017,
  author        = {Lehmann, Marius and Schmidt, J{\"u}rgen and Salo, Heikki},
  title         = {Viscous Overstability in {S}aturn's Rings: Influence of Collective Self-gravity},
  journal       = {The Astrophysical Journal},
  year          = {2017},
  volume        = {851},
  pages         = {125},
  eprint        = {1804.07968},
  archivePrefix = {arXiv},
  primaryClass  = {astro-ph.EP}
}"""

SOFTWARE_TEMPLATE = r"""@software{ringlab,
  title   = {ringlab: viscous overstability in {S}aturn's dense rings (ringcore numerical core and web lab)},
  author  = {{The ringlab developers}},
  version = {VERSION},
  note    = {commit COMMIT; implements the model of Lehmann, Schmidt and Salo (2017)},
  license = {BSD-3-Clause}
}"""


def software_bibtex() -> str:
    """BibTeX entry of this software, with the running version and commit."""
    return SOFTWARE_TEMPLATE.replace("VERSION", __version__).replace("COMMIT", commit())


def cite(show: bool = True) -> str:
    """The references to cite for work done with ringcore, as BibTeX.

    Parameters
    ----------
    show : bool, optional
        Print the references (default ``True``).

    Returns
    -------
    str
        Two BibTeX entries: the paper (Lehmann, Schmidt & Salo 2017, ApJ 851:125) and ringlab itself
        (version and git commit of the running code).

    Examples
    --------
    >>> import ringcore
    >>> text = ringcore.cite(show=False)
    >>> "Lehmann2017" in text and "@software{ringlab" in text
    True
    """
    text = ("% The model and its numerical methods:\n" + PAPER_BIBTEX + "\n\n% The software:\n"
            + software_bibtex() + "\n")
    if show:
        print(text, end="")
    return text
