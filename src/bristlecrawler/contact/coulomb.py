"""Penalty / augmented-Lagrangian Coulomb friction for one contact point in 2-D.

Kinematics of a contact point: the signed gap ``g`` (mm, negative when penetrating) and a
tangential coordinate ``s`` (mm) of its closest point along the surface, preferably the arc
length of :func:`~bristlecrawler.contact.profile.project` (any coordinate that grows by the
tangential travel works, e.g. the closest-point x on a flat plane). The history variable is
the stick *anchor* ``a`` (mm): the value of ``s`` where the point sticks.

Normal part (penalty regularised, optionally augmented by a multiplier ``lambda_n``, N)::

    p_N = max(lambda_n - k_n g, 0)                    (N, compressive force >= 0)
    W_N = max(lambda_n - k_n g, 0)^2 / (2 k_n)         (mJ),   dW_N/dg = -p_N

With ``lambda_n = 0`` this is the plain penalty ``k_n <-g>^2 / 2``; the Uzawa update
``lambda_n <- p_N`` drives the penetration to zero (Wriggers, Computational Contact
Mechanics, 2nd ed., Springer 2006, Sec. 6.3 and 10.3).

Tangential part: the elastic-perfectly-plastic return mapping (Wriggers 2006, Sec. 5.2.2;
Simo & Hughes, Computational Inelasticity, Sec. 1.2), exact for one backward-Euler step with
the limit ``mu p_N`` of the end of the step::

    trial  delta = s - a,   f_trial = k_t delta
    stick  |f_trial| <= mu p_N :  f = f_trial,                a unchanged  (see STICK_TOL)
    slip   otherwise           :  f = mu p_N sign(delta),     a = s - sign(delta) mu p_N / k_t

``f`` is the derivative of the incremental frictional pseudo-potential (a Huber function)
``psi(delta) = k_t delta^2 / 2`` for ``|delta| <= mu p_N / k_t`` and
``mu p_N (|delta| - mu p_N / (2 k_t))`` beyond, so the step's incremental potential is
``Phi = W_N(g) + psi(s - a)`` with ``p_N`` frozen in ``psi``: ``dPhi/dg = -p_N`` and
``dPhi/ds = f``. The force of the substrate on the point is ``p_N n - f t`` (n outward normal,
t tangent), i.e. ``-dPhi/dx``.

"Stick" with a penalty is an elastic micro-displacement ``|delta| = |f| / k_t``;
:meth:`CoulombLaw.for_reference_load` picks ``k_t`` so that it stays below a given drift
(1e-4 mm by default) at the friction limit of a reference load, and ``k_n`` so that the
penetration stays below 1e-3 mm at that load. The dissipation of a step is exactly
``mu p_N |Delta a|`` (the slip increment is the anchor's travel).

All functions are elementwise in their array arguments (so they act on many contact points
at once and are ``jax.vmap``-able), pure, and differentiable: ``jax.grad`` of
:func:`incremental_potential` gives the generalised forces, ``jax.hessian`` its symmetric
(frozen-``p_N``) tangent; ``jax.jacfwd`` of :func:`generalized_forces` gives the full,
non-symmetric consistent tangent of the non-associative Coulomb law.
"""

from __future__ import annotations

import abc
import warnings
from typing import ClassVar, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import as_float_leaf, is_concrete, pytree
from bristlecrawler.errors import InputError
from bristlecrawler.states import ContactState

OPEN, STICK, SLIP = ContactState.OPEN, ContactState.STICK, ContactState.SLIP

#: Relative width of the slip side of the stick/slip boundary: a point sticks only while
#: ``|f_trial| <= (1 - STICK_TOL) mu p_N``. A point committed in slip has its anchor put at
#: ``s - sign mu p_N / k_t``, i.e. *on* the boundary, so at the start of the next step (the
#: tangent predictor's linearisation point, and Newton's first iterate) round-off in
#: ``s - a`` (about eps |s| / (mu p_N / k_t), 1e-10 for s ~ 100 mm and a stick drift of
#: 1e-4 mm) decided between the stick tangent and the slip one. With the band a point that
#: slipped stays on the slip branch until its trial force drops; the force changes by at
#: most ``STICK_TOL mu p_N``. Measured: a bristle tip
#: sliding steadily got the stick tangent on about every other step and needed 2.87 Newton
#: iterations per step, 1.90 with the band; the paper crawler's first cycle completed with
#: the band in both runs made, and stopped in its first re-extension without it in all
#: three (a land edge pushed beyond the penetration limit). The price: starting on the slip
#: tangent, a point that meets a wall while slipping can make Newton cycle between slip in
#: both directions; the monotone line search breaks that cycle, the growth one does not.
STICK_TOL = 1e-8

#: Static normal load on one bristle tip in the paper's prototype (55 g on two bristles,
#: Section 2), N: 0.055 kg * 9.81 m/s^2 / 2.
PAPER_TIP_LOAD = 0.055 * 9.81 / 2


class FrictionLaw(abc.ABC):
    """What the contact kernels (point, disc and corner terms) ask of a friction law.

    A law is a frozen PyTree dataclass (:func:`~bristlecrawler._pytree.pytree`) whose
    leaves are its parameters (so they change without a recompile), subclassing this class
    with its name: ``class MyLaw(CoulombLaw, law="mine")`` registers it, and
    :meth:`of` finds it by that name. A law of the package's (imported by
    :mod:`bristlecrawler.contact`, so registered before the crawler's settings are read)
    is a word of the scenario's ``contact.friction``; the crawler builds it with
    ``for_reference_load`` (:class:`CoulombLaw`'s, which a subclass inherits, its own
    parameters through ``at_load``). A law acts at each contact point. Every argument
    broadcasts over contact points. The hooks a law defines:

    * :meth:`normal_force` ``(g, lambda_n) -> p_N`` (N) and :meth:`normal_energy` (mJ,
      ``d/dg = -p_N``): the normal part;
    * :meth:`limit` ``(p_N) -> F`` (N): the largest tangential resistance at normal force
      ``p_N``;
    * :meth:`penetration` ``(p_N)`` (mm) and :meth:`stored_energy` ``(p_N, f_t)`` (mJ):
      what the run's limit on penetration and its energy balance read;
    * the attribute ``k_t`` (N/mm): the stick penalty of the return mapping.

    From them the base class gives what the kernels call: :meth:`step` (one backward-Euler
    return mapping, :func:`return_map`), :meth:`forces` (the residual's ``(dPhi/dg,
    dPhi/ds)``, differentiable for the tangent) and :meth:`potential` (an incremental
    potential whose gradient is ``forces``). A law of another kind (rate-dependent,
    directional) may override those three instead.
    """

    #: Registered laws by name (:meth:`of`).
    laws: ClassVar[dict[str, type[FrictionLaw]]] = {}
    #: The law's name in a scenario (``contact.friction``).
    name: ClassVar[str] = ""

    def __init_subclass__(cls, law: str | None = None, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if law is not None:
            cls.name = law
            FrictionLaw.laws[law] = cls

    @classmethod
    def of(cls, name: str) -> type[FrictionLaw]:
        """The law registered as ``name``; InputError naming the known ones."""
        try:
            return FrictionLaw.laws[name]
        except KeyError:
            known = ", ".join(sorted(FrictionLaw.laws))
            raise InputError(f"unknown friction law {name!r}; known: {known}") from None

    @abc.abstractmethod
    def normal_force(self, g, lambda_n=0.0) -> jax.Array:
        """The normal contact force at gap ``g`` (mm), N (>= 0)."""

    @abc.abstractmethod
    def normal_energy(self, g, lambda_n=0.0) -> jax.Array:
        """The normal part's energy at gap ``g`` (mm), mJ; ``d/dg = -normal_force``."""

    @abc.abstractmethod
    def limit(self, p_n) -> jax.Array:
        """The friction limit at normal force ``p_n`` (N), N."""

    @abc.abstractmethod
    def penetration(self, p_n) -> jax.Array:
        """The penetration at which the normal force is ``p_n`` (N), mm."""

    @abc.abstractmethod
    def stored_energy(self, p_n, f_t) -> jax.Array:
        """The elastic energy the regularisation holds at normal force ``p_n`` and
        tangential resistance ``f_t`` (N), mJ."""

    def step(self, g, s, anchor, lambda_n=0.0, mode=None) -> CoulombStep:
        """:func:`return_map` with this law: the step's normal force, resistance, new
        anchor, status, slip, dissipation and stored energy."""
        return return_map(g, s, anchor, self, lambda_n, mode)

    def forces(self, g, s, anchor, lambda_n=0.0, mode=None) -> tuple[jax.Array, jax.Array]:
        """:func:`generalized_forces` with this law: ``(dPhi/dg, dPhi/ds) = (-p_N, f_t)``."""
        return generalized_forces(g, s, anchor, self, lambda_n, mode)

    def potential(self, g, s, anchor, lambda_n=0.0) -> jax.Array:
        """:func:`incremental_potential` with this law, mJ (summed over points)."""
        return incremental_potential(g, s, anchor, self, lambda_n)


@pytree()
class CoulombLaw(FrictionLaw, law="coulomb"):
    """Coulomb friction with penalty regularisation: the :class:`FrictionLaw` of the
    crawler's contact terms.

    Attributes:
        mu: friction coefficient, dimensionless, >= 0.
        k_n: normal penalty stiffness, N/mm, > 0.
        k_t: tangential (stick) penalty stiffness, N/mm, > 0.
    """

    mu: jax.Array
    k_n: jax.Array
    k_t: jax.Array

    def normal_force(self, g, lambda_n=0.0) -> jax.Array:
        """The penalty's p_N = max(lambda_n - k_N g, 0), N."""
        return normal_force(g, self, lambda_n)

    def normal_energy(self, g, lambda_n=0.0) -> jax.Array:
        """The penalty's max(lambda_n - k_N g, 0)^2 / (2 k_N), mJ."""
        return normal_energy(g, self, lambda_n)

    def limit(self, p_n) -> jax.Array:
        """Coulomb's mu p_N, N."""
        return self.mu * p_n

    def penetration(self, p_n) -> jax.Array:
        """The penalty's penetration at normal force ``p_n``: p_N / k_N, mm."""
        return p_n / self.k_n

    def stored_energy(self, p_n, f_t) -> jax.Array:
        """The penalty springs' energy at ``p_n`` and ``f_t``: p_N^2/(2 k_N) + f_t^2/(2 k_t),
        mJ."""
        return 0.5 * p_n**2 / self.k_n + 0.5 * f_t**2 / self.k_t

    def __post_init__(self) -> None:
        vals = [as_float_leaf(self, n) for n in ("mu", "k_n", "k_t")]
        if not is_concrete(*vals):
            return
        mu, k_n, k_t = (np.asarray(v) for v in vals)
        if not np.all(np.isfinite(mu) & (mu >= 0)):
            raise InputError(f"friction coefficient mu must be finite and >= 0, got {mu}")
        for name, k in (("k_n", k_n), ("k_t", k_t)):
            if not np.all(np.isfinite(k) & (k > 0)):
                raise InputError(f"penalty stiffness {name} must be finite and > 0 N/mm, got {k}")

    @classmethod
    def for_reference_load(
        cls,
        mu: float,
        load: float = PAPER_TIP_LOAD,
        design_penetration: float = 1e-3,
        max_stick_drift: float = 1e-4,
        **options: float,
    ) -> CoulombLaw:
        """Penalties sized for a reference normal load (``options``: the law's own
        parameters, :meth:`at_load`).

        Args:
            mu: friction coefficient, dimensionless.
            load: reference normal load, N (default: the paper's static load per bristle,
                0.27 N; pass the largest load expected, dynamic peaks included).
            design_penetration: penetration at ``load``, mm (default 1 micrometre): it
                sizes the penalty (``max_penetration`` before, still taken with a
                DeprecationWarning); a run's limit on penetration is another setting,
                ``Integrator.penetration_limit``.
            max_stick_drift: elastic tangential displacement allowed in stick at the
                friction limit ``mu * load``, mm (default 1e-4 mm).

        Returns ``k_n = load / design_penetration`` and
        ``k_t = max(mu, 0.01) * load / max_stick_drift`` (N/mm); the floor keeps ``k_t``
        positive and meaningful for frictionless contact.
        """
        if "max_penetration" in options:
            warnings.warn(
                "for_reference_load(max_penetration=...) is deprecated: use design_penetration",
                DeprecationWarning,
                stacklevel=2,
            )
            design_penetration = options.pop("max_penetration")
        for name, v in (
            ("load", load),
            ("design_penetration", design_penetration),
            ("max_stick_drift", max_stick_drift),
        ):
            if not (np.isfinite(v) and v > 0):
                raise InputError(f"{name} must be a positive finite number, got {v!r}")
        if not (np.isfinite(mu) and mu >= 0):
            raise InputError(f"friction coefficient mu must be finite and >= 0, got {mu!r}")
        k_n = load / design_penetration
        k_t = max(mu, 0.01) * load / max_stick_drift
        return cls.at_load(mu, k_n, k_t, load, **options)

    @classmethod
    def at_load(cls, mu: float, k_n: float, k_t: float, load: float, **options) -> CoulombLaw:
        """The law with these penalties (N/mm) sized at the reference ``load`` (N), which
        Coulomb's law does not keep; TypeError for an option it does not have."""
        if options:
            raise TypeError(f"for_reference_load got unexpected keywords {sorted(options)}")
        return cls(mu=mu, k_n=k_n, k_t=k_t)


class CoulombStep(NamedTuple):
    """Result of one return mapping (arrays broadcast like the inputs).

    Attributes:
        p_n: normal contact force, N (>= 0; acts along the outward normal on the point).
        f_t: tangential resistance ``dPhi/ds``, N; the force on the point is ``-f_t`` along t.
        anchor: updated stick anchor, mm.
        state: 0 open, 1 stick, 2 slip (int).
        slip: slip increment of the step ``|Delta anchor|``, mm (0 in stick and open).
        dissipation: frictional dissipation of the step, the limit times the slip
            (``mu p_N slip`` for Coulomb's law), mJ.
        stored: elastic penalty energy at the end of the step, mJ.
    """

    p_n: jax.Array
    f_t: jax.Array
    anchor: jax.Array
    state: jax.Array
    slip: jax.Array
    dissipation: jax.Array
    stored: jax.Array


def normal_force(g: jax.Array, law: CoulombLaw, lambda_n: jax.Array = 0.0) -> jax.Array:
    """Normal contact force p_N = max(lambda_n - k_n g, 0), N, for gap ``g`` (mm)."""
    return jnp.maximum(lambda_n - law.k_n * g, 0.0)


def normal_energy(g: jax.Array, law: CoulombLaw, lambda_n: jax.Array = 0.0) -> jax.Array:
    """Penalty (augmented-Lagrangian) normal energy, mJ; ``d/dg = -p_N``."""
    return 0.5 * normal_force(g, law, lambda_n) ** 2 / law.k_n


def friction_potential(delta: jax.Array, limit: jax.Array, k_t: jax.Array) -> jax.Array:
    """Incremental frictional pseudo-potential (Huber function), mJ.

    Args:
        delta: trial tangential displacement from the anchor ``s - a``, mm.
        limit: friction limit ``mu p_N``, N (>= 0).
        k_t: tangential penalty stiffness, N/mm.
    """
    d_c = limit / k_t
    ad = jnp.abs(delta)
    return jnp.where(ad <= (1.0 - STICK_TOL) * d_c, 0.5 * k_t * delta**2, limit * (ad - 0.5 * d_c))


def frozen_status(state: jax.Array, freeze) -> jax.Array | None:
    """The ``mode`` argument of :func:`return_map` for a contact residual evaluated with
    ``freeze`` (bool, traced or not; :func:`bristlecrawler.fe.newton.newton`): the
    committed ``state`` where it is True, the return mapping's own (-1) where not, and
    None (no selection in the program) when it is the Python constant False."""
    if freeze is False:
        return None
    return jnp.where(freeze, state, -1)


def return_map(
    g: jax.Array,
    s: jax.Array,
    anchor: jax.Array,
    law: FrictionLaw,
    lambda_n: jax.Array = 0.0,
    mode: jax.Array | None = None,
) -> CoulombStep:
    """One backward-Euler step of penalty Coulomb friction (see the module docstring).

    Args:
        g: gap at the end of the step, mm.
        s: tangential coordinate at the end of the step, mm.
        anchor: stick anchor from the previous step, mm.
        law: the :class:`FrictionLaw` (its normal force, limit and ``k_t``).
        lambda_n: augmented-Lagrangian normal multiplier, N (0 for pure penalty).
        mode: optional frozen status per point (int): where it is STICK (SLIP) a closed
            point takes the stick (slip) branch whatever its trial force; elsewhere
            (OPEN, or any other value) the return mapping decides. Newton's first
            iterations of a step use the committed states (:func:`fe.newton.newton`'s
            ``freeze``); the result is then not Coulomb's law, only a start for it.

    An open contact (p_N = 0) moves its anchor to ``s``, so a later touchdown starts in
    stick at the point of the last open step.
    """
    p_n = law.normal_force(g, lambda_n)
    limit = law.limit(p_n)
    delta = s - anchor
    f_trial = law.k_t * delta
    # An open point never sticks: with a zero limit and the anchor at s (delta = 0, as at
    # the first Newton iterate after an open step) the stick branch would put a spurious
    # tangential spring k_t into the tangent of a point that carries no force.
    sticks = (jnp.abs(f_trial) <= (1.0 - STICK_TOL) * limit) & (p_n > 0.0)
    if mode is not None:
        sticks = jnp.where(mode == STICK, p_n > 0.0, jnp.where(mode == SLIP, False, sticks))
    sign = jnp.sign(delta)
    f_t = jnp.where(sticks, f_trial, limit * sign)
    new_anchor = jnp.where(sticks, anchor, s - sign * limit / law.k_t)
    is_open = p_n <= 0.0
    new_anchor = jnp.where(is_open, s, new_anchor)
    slip = jnp.where(is_open, 0.0, jnp.abs(new_anchor - anchor))
    state = jnp.where(is_open, OPEN, jnp.where(sticks, STICK, SLIP))
    stored = law.normal_energy(g, lambda_n) + 0.5 * f_t**2 / law.k_t
    return CoulombStep(
        p_n=p_n,
        f_t=f_t,
        anchor=new_anchor,
        state=state,
        slip=slip,
        dissipation=limit * slip,
        stored=stored,
    )


def incremental_potential(
    g: jax.Array,
    s: jax.Array,
    anchor: jax.Array,
    law: FrictionLaw,
    lambda_n: jax.Array = 0.0,
) -> jax.Array:
    """Incremental potential of one step ``W_N(g) + psi(s - a; mu p_N)``, mJ (summed).

    ``p_N`` inside ``psi`` is held fixed (``stop_gradient``) because Coulomb friction is not
    associative: without it ``d/dg`` would pick up a spurious ``dpsi/dp_N`` normal force.
    ``jax.grad`` w.r.t. (g, s) gives exactly (-p_N, f_t) of :func:`return_map`;
    ``jax.hessian`` gives the tangent with ``p_N`` frozen (exact in stick; in slip it lacks
    the ``mu k_n`` normal-to-tangential coupling, see :func:`generalized_forces`).
    Returns the sum over contact points so that gradients act per point.
    """
    p_n = jax.lax.stop_gradient(law.normal_force(g, lambda_n))
    psi = friction_potential(s - anchor, law.limit(p_n), law.k_t)
    return jnp.sum(law.normal_energy(g, lambda_n) + psi)


def generalized_forces(
    g: jax.Array,
    s: jax.Array,
    anchor: jax.Array,
    law: FrictionLaw,
    lambda_n: jax.Array = 0.0,
    mode: jax.Array | None = None,
) -> tuple[jax.Array, jax.Array]:
    """``(dPhi/dg, dPhi/ds) = (-p_N, f_t)``, N, with the full dependence on ``g``.

    ``jax.jacfwd`` of this (w.r.t. g and s) is the consistent, non-symmetric tangent: in
    stick ``[[k_n, 0], [0, k_t]]``, in slip ``[[k_n, 0], [-mu k_n sign(delta), 0]]`` (for
    a closed contact). ``mode``: frozen statuses, see :func:`return_map`.
    """
    step = return_map(g, s, anchor, law, lambda_n, mode)
    return -step.p_n, step.f_t
