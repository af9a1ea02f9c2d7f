"""Nonlinear planar finite elements for the bristle crawler (paper Section 3), in JAX.

Corotational beams with tapered sections, point masses, rigid bodies, springs, rigid links
(with prescribed stretch: the actuated body), prescribed motions and dead loads; static
Newton with load stepping, modal analysis, Newmark / HHT-alpha dynamics with adaptive steps.
Float64 throughout (enabled here, once). Units: mm, N, s, tonne.
"""

from __future__ import annotations

import jax

jax.config.update("jax_enable_x64", True)
