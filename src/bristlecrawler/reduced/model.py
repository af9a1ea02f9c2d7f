"""The plug-in point of the reduced models: an abstract class with every hook named.

A reduced model is N bristles on a rigid body of N-1 actuated segments, each bristle a
spring of stiffness k (N/mm) to a tip that resists sliding by a rate-independent law, run
quasi-statically by an exact, event-by-event solver. :func:`~bristlecrawler.reduced.simulate`,
the prediction, the design studies and the NetCDF output ask a model only through these
hooks, never for its class. Adding a model is one file: a frozen dataclass that subclasses
:class:`ReducedModel`, names itself (``name = "..."``, how ``from_drag(model=...)`` and the
studies call it) and implements every abstract hook; its tests beside it.
"""

from __future__ import annotations

import abc
from typing import Any, ClassVar


class ReducedModel(abc.ABC):
    """A reduced crawler model (see the module). Subclasses are frozen dataclasses with
    a ``segment_lengths`` field (the rest lengths of the N-1 body segments, mm)."""

    #: The model's name (``"paper"``, ``"texture"``).
    name: ClassVar[str]
    #: Every model by its name, filled as the models' modules are imported.
    registered: ClassVar[dict[str, type[ReducedModel]]] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "name" in cls.__dict__:
            ReducedModel.registered[cls.name] = cls

    @property
    @abc.abstractmethod
    def n_bristles(self) -> int:
        """Number of bristles N."""

    @property
    @abc.abstractmethod
    def length(self) -> float:
        """Rest distance between the first and the last bristle, mm."""

    @abc.abstractmethod
    def check_stroke(self, max_shortening) -> None:
        """InputError unless each segment's peak shortening (mm, one value or N-1) is
        smaller than its rest length."""

    @abc.abstractmethod
    def solve(self, t, shortening, cycle_bounds=None):
        """The quasi-static evolution for sampled segment shortenings: a
        :class:`~bristlecrawler.reduced.ReducedResult` (``t`` in s, shape (M,);
        ``shortening`` in mm, shape (M, N-1); ``cycle_bounds`` the sample indices where
        cycles start)."""

    @abc.abstractmethod
    def paper_crawler(self):
        """The paper's model (one k, F_p and F_n per bristle) that stands for this one:
        itself for the paper's model, a texture's means for a texture."""

    @abc.abstractmethod
    def texture_laws(self) -> tuple | None:
        """Each bristle's :class:`~bristlecrawler.results.TextureLaw`, or None where the
        resistance does not depend on the tip's position (the paper's law)."""

    @classmethod
    @abc.abstractmethod
    def from_drag(cls, drag, n_bristles: int = 2, length: float = 100.0, **options):
        """The model whose bristles all have what a drag test gives (a
        :class:`~bristlecrawler.results.DragSummary`, a drag result or a summary mapping;
        a sequence of them gives each bristle its own), spread evenly over ``length`` mm
        or placed by ``segment_lengths``."""
