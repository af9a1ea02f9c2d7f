"""bristlecrawler: crawlers that move by directional friction.

Units throughout: mm, N, s, tonne (so stresses in MPa, energies in mJ = N mm).
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
