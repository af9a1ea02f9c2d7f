"""Named state codes with one meaning across the package (stored as small integers in
results and NetCDF files, so the values are part of the file format)."""

from __future__ import annotations

import enum


class ContactState(enum.IntEnum):
    """A contact point (or a bristle tip) of the FE model against the substrate."""

    OPEN = 0
    STICK = 1
    SLIP = 2


class Slip(enum.IntEnum):
    """A bristle of the reduced model, always in contact: the sign of its sliding velocity
    (NONE: it sticks; FORWARD: along the grain, +x; BACKWARD: against it)."""

    BACKWARD = -1
    NONE = 0
    FORWARD = 1
