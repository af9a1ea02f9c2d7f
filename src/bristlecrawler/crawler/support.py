"""Whether a bristle can carry its share of the crawler's weight on its tip.

A bristle inclined by alpha from the vertical, tapered from h0 at the clamp to h1 at the
tip, stands on its tip with its lower face sloping down towards the tip; the lowest corner
of its clamp section stands

    c = L cos(alpha) - (h0 - h1)/2 sin(alpha)

above the tip's lower corner (zero at tan(alpha) = 2 L / (h0 - h1): 75.96 degrees for the
paper's bristle, where the lower face is level). Under its share W of the weight the clamp
sinks by W C_yy, with C_yy the vertical compliance of the tapered cantilever at its tip
held on the substrate. A tip that sticks is held horizontally too, the stiffest support
friction can give; that compliance, C_yy - C_xy^2 / C_xx (linear beam theory, axial,
bending and, where the bristle has it, shear compliance), is a lower bound of the sag. A
bristle whose lower bound reaches the clearance lies down on its face until its clamp
meets the substrate: the crawler would stand on its clamps, not on its bristles' tips.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from bristlecrawler.errors import InputError

#: Timoshenko's shear coefficient of a rectangular section.
_KAPPA = 5.0 / 6.0


def _axial(E, b, h0, h1, L) -> float:
    """int_0^L dx / (E b h(x)), mm/N."""
    if h1 == h0:
        return L / (E * b * h0)
    return L * math.log(h1 / h0) / (E * b * (h1 - h0))


def _bending(E, b, h0, h1, L) -> float:
    """Tip deflection per tip load of the tapered cantilever, int (L - x)^2 / (E I) dx with
    I = b h^3 / 12, h linear from h0 to h1, mm/N."""
    if h1 == h0:
        return 4.0 * L**3 / (E * b * h0**3)
    c = (h1 - h0) / L
    bracket = 1.5 + math.log(h1 / h0) - 2.0 * h1 / h0 + h1**2 / (2.0 * h0**2)
    return 12.0 / (E * b * c**3) * bracket


@dataclass(frozen=True)
class Support:
    """A bristle's stand under its share of the weight (mm, N)."""

    clearance_mm: float
    load_N: float
    sag_mm: float

    @property
    def carries(self) -> bool:
        return self.sag_mm < self.clearance_mm


def support(bristle, load: float) -> Support:
    """The clearance of ``bristle``'s clamp corner over its tip and the least sag (tip
    held) under ``load`` N (see the module)."""
    E, b, L = bristle.youngs_modulus, bristle.width, bristle.length
    h0, h1 = bristle.thickness_clamp, bristle.thickness_tip
    a = abs(bristle.alpha)
    fa = _axial(E, b, h0, h1, L)
    fb = _bending(E, b, h0, h1, L)
    if bristle.shear:
        fb += _axial(_KAPPA * E / (2.0 * (1.0 + bristle.poisson_ratio)), b, h0, h1, L)
    s, c = math.sin(a), math.cos(a)
    cxx = s * s * fa + c * c * fb
    cyy = c * c * fa + s * s * fb
    cxy = s * c * (fb - fa)
    held = cyy - cxy * cxy / cxx
    clearance = L * c - 0.5 * (h0 - h1) * s
    return Support(clearance_mm=clearance, load_N=load, sag_mm=load * held)


def check_support(spec) -> None:
    """Raise :class:`InputError` unless each bristle of ``spec`` (a ``CrawlerSpec``) carries
    its share of the weight on its tip."""
    weight = (spec.body.mass + sum(b.mass for b in spec.bristles)) * spec.gravity
    for i, b in enumerate(spec.bristles):
        st = support(b, weight / len(spec.bristles))
        if not st.carries:
            raise InputError(
                f"bristles[{i}] cannot carry the body: at alpha_deg = {b.alpha_deg:g} its "
                f"clamp's lower corner stands {st.clearance_mm:.3g} mm above its tip, and "
                f"its share of the weight ({st.load_N:.3g} N) bends it down by at least "
                f"{st.sag_mm:.3g} mm (beam theory, tip held), so it would lie on its face "
                "with the crawler on its clamps; incline it less or make it stiffer"
            )
