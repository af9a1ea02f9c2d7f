"""Float64 JAX for the whole package, switched on in this one place.

The mechanics needs float64 (contact penalties of 1e4-1e6 N/mm against forces of 1e-4 N);
``fe`` and ``contact`` import this module before any of their JAX code runs.
"""

import jax

jax.config.update("jax_enable_x64", True)
