"""Friction that grows as a power of the normal load: F = mu L (p_N / L)^m.

Rubber and soft elastomers on a hard counterface do not follow Amontons-Coulomb: with a
shear strength of the interface and a Hertzian real contact area (which grows as the
load to the power 2/3) the friction force grows as N^(2/3) (A. Schallamach, "The load
dependence of rubber friction", Proc. Phys. Soc. B 65, 657, 1952). This law takes the
limit of the tangential resistance as

    F(p_N) = mu L (p_N / L)^m,     0.5 <= m <= 1,

with ``L`` the reference load at which the coefficient ``mu`` is measured (in the crawler
``contact.friction_load``, by default the weight on one bristle): at ``p_N = L`` it is Coulomb's
``mu L``; below ``L`` it resists more than Coulomb, above less. ``m = 1`` is Coulomb's law
exactly. Everything else (the penalty normal part, the stick penalty ``k_t``, the return
mapping, the exact dissipation ``F |Delta a|``) is :class:`CoulombLaw`'s.

The law acts at each contact point, as the kernels apply every law: where several points
of one bristle press the substrate at once (points on every node, a land edge on the face
beside the tip's end), each takes the law of its own load, and for m < 1 their sum is more
than the law of their summed load, so the result depends on how the contact is
discretised. Its slip tangent d F / d p_N = m mu (p_N / L)^(m - 1) has no bound as a
point's load goes to zero (at touchdown).

The scenario chooses it with ``contact.friction = "power"`` and ``contact.friction_exponent``.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import as_float_leaf, is_concrete, pytree
from bristlecrawler.contact.coulomb import CoulombLaw
from bristlecrawler.errors import InputError

#: The exponent of a Hertzian contact with a constant interfacial shear strength.
HERTZ_EXPONENT = 2.0 / 3.0
#: The range of exponents this law takes: 1 is Coulomb's; below 1/2 the resistance of a
#: lightly loaded point rises so steeply with its load that the slip tangent (d F / d p_N,
#: infinite at touchdown for m < 1) dominates the contact stiffness.
EXPONENT_RANGE = (0.5, 1.0)


@pytree()
class PowerLaw(CoulombLaw, law="power"):
    """Friction limit ``mu load (p_N / load)^exponent`` with the penalty normal part and
    return mapping of :class:`CoulombLaw`.

    Attributes:
        mu: friction coefficient at the reference load, dimensionless, >= 0.
        k_n: normal penalty stiffness, N/mm, > 0.
        k_t: tangential (stick) penalty stiffness, N/mm, > 0.
        exponent: m, dimensionless, in [0.5, 1].
        load: the reference load L, N, > 0.
    """

    exponent: jax.Array
    load: jax.Array

    def limit(self, p_n) -> jax.Array:
        """mu L (p_N / L)^m, N (0 where p_N = 0, with a finite derivative there for the
        open branch)."""
        ratio = p_n / self.load
        safe = jnp.where(ratio > 0.0, ratio, 1.0)
        return jnp.where(ratio > 0.0, self.mu * self.load * safe**self.exponent, 0.0)

    def __post_init__(self) -> None:
        super().__post_init__()
        vals = [as_float_leaf(self, n) for n in ("exponent", "load")]
        if not is_concrete(*vals):
            return
        m, load = (np.asarray(v) for v in vals)
        lo, hi = EXPONENT_RANGE
        if not np.all(np.isfinite(m) & (m >= lo) & (m <= hi)):
            raise InputError(f"friction exponent must be in [{lo:g}, {hi:g}], got {m}")
        if not np.all(np.isfinite(load) & (load > 0)):
            raise InputError(f"reference load must be finite and > 0 N, got {load}")

    @classmethod
    def at_load(
        cls,
        mu: float,
        k_n: float,
        k_t: float,
        load: float,
        exponent: float = HERTZ_EXPONENT,
        reference: float | None = None,
    ) -> PowerLaw:
        """The law with the penalties of :meth:`CoulombLaw.for_reference_load` (sized at
        ``load``), ``exponent`` its m (default 2/3, a Hertzian contact) and ``reference``
        its L (N; default ``load``): the penalties are numerics, L is physics."""
        L = load if reference is None else reference
        return cls(mu=mu, k_n=k_n, k_t=k_t, exponent=exponent, load=L)
