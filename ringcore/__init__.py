"""ringcore: numerical core for viscous overstability in dense planetary rings.

After Lehmann, Schmidt & Salo (2017, ApJ 851:125). Modules:

- :mod:`ringcore.units`   constants and the paper's dimensionless scalings
- :mod:`ringcore.params`  the paper's parameter sets (:class:`RingParams`)
- :mod:`ringcore.linear`  exact linear theory, eq. (matni)
"""
from . import params, units
from .params import RingParams

__version__ = "0.1.0"
__all__ = ["params", "units", "RingParams", "__version__"]
