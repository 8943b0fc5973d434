"""ringcore: numerical core for viscous overstability in dense planetary rings.

After Lehmann, Schmidt & Salo (2017, ApJ 851:125). Modules:

- :mod:`ringcore.units`   constants and the paper's dimensionless scalings
- :mod:`ringcore.params`  the paper's parameter sets (:class:`RingParams`)
- :mod:`ringcore.linear`  exact linear theory, Eq. (17) [matni]

:func:`cite` prints what to cite (the paper and this software, BibTeX); ``__version__`` is derived from
git (:mod:`ringcore.provenance`).
"""
from . import params, units
from .citation import cite
from .params import RingParams
from .provenance import __version__

__all__ = ["params", "units", "RingParams", "cite", "__version__"]
