"""The finite-element bristle crawler (paper Section 3) as a library.

Describe a design with plain frozen dataclasses, build it, run it in stages, read the
result::

    from bristlecrawler.crawler import CrawlerSpec, build, run

    spec = CrawlerSpec.paper().with_bristles(3, alpha_deg=30.0)
    history = run(build(spec))
    history.net_advance, history.to_dataset()

* design: :class:`CrawlerSpec` with :class:`Body`, :class:`Bristle`, :class:`Contact`,
  :class:`Damping`, :class:`Actuation`, :class:`Solver` (mm, N, s, t, MPa);
* :func:`build` -> :class:`CrawlerModel` (the FE model and its node bookkeeping);
* :func:`run` with stages :class:`Settle`, :class:`ModalDamping`, :class:`Stroke` (the
  paper's analysis steps, the default; :class:`Hold` and your own stages after them)
  and a progress callback -> :class:`CrawlerHistory` (``.summary()``, ``.to_dataset()``);
* :func:`run_batch`: designs of one structure (see :mod:`.structure`) in one compiled
  program -> :class:`BatchResult`.
"""

from bristlecrawler.crawler.batch import BatchResult, group, run_batch
from bristlecrawler.crawler.history import (
    STRAIN_LIMIT,
    TIP_OPEN,
    TIP_SLIP,
    TIP_STICK,
    CrawlerHistory,
    StrainPeak,
)
from bristlecrawler.crawler.model import CrawlerModel, build
from bristlecrawler.crawler.runner import (
    DEFAULT_STAGES,
    Advance,
    Hold,
    ModalDamping,
    Progress,
    RunContext,
    RunOptions,
    Settle,
    Stage,
    SteppedStage,
    Stroke,
    run,
)
from bristlecrawler.crawler.spec import (
    Actuation,
    Body,
    Bristle,
    Contact,
    CrawlerSpec,
    Damping,
    Solver,
    uniform_bristles,
)

__all__ = [
    "DEFAULT_STAGES",
    "STRAIN_LIMIT",
    "TIP_OPEN",
    "TIP_SLIP",
    "TIP_STICK",
    "Actuation",
    "Advance",
    "BatchResult",
    "Body",
    "Bristle",
    "Contact",
    "CrawlerHistory",
    "CrawlerModel",
    "CrawlerSpec",
    "Damping",
    "Hold",
    "ModalDamping",
    "Progress",
    "RunContext",
    "RunOptions",
    "Settle",
    "Solver",
    "Stage",
    "SteppedStage",
    "StrainPeak",
    "Stroke",
    "build",
    "group",
    "run",
    "run_batch",
    "uniform_bristles",
]
