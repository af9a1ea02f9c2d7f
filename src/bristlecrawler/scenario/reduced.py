"""The reduced-model run configuration (CLI options or a TOML table), validated by pydantic,
and the crawler and gait it describes (:func:`build`)."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from bristlecrawler.reduced.crawler import (
    DEFAULT_FN_OVER_FP,
    PAPER_CYCLES,
    PAPER_FP,
    PAPER_K,
    PAPER_LENGTH,
    PAPER_PERIOD,
    PAPER_S_MAX,
    ReducedCrawler,
)
from bristlecrawler.reduced.gaits import breathing, peristaltic
from bristlecrawler.reduced.strokes import Sin2Stroke, TriangleStroke, read_history_csv

#: Bounds of the physical parameters: lengths in mm (10 m), forces in N; F_p/k in mm.
MAX_LENGTH = 1e4
MIN_FORCE = 1e-9
MAX_FORCE = 1e6
MIN_FP_OVER_K = 1e-9
#: Most samples of a run (cycles x samples per cycle): about a gigabyte of results.
MAX_SAMPLES = 1e8


class ReducedConfig(BaseModel):
    """Parameters of a reduced-model run. Defaults reproduce the paper (Section 4)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    s_max: float = Field(
        PAPER_S_MAX,
        gt=0,
        le=MAX_LENGTH,
        allow_inf_nan=False,
        description="peak shortening s~ of each segment, mm",
    )
    fp: float = Field(
        PAPER_FP,
        ge=MIN_FORCE,
        le=MAX_FORCE,
        allow_inf_nan=False,
        description="F_p, resistance along the grain, N",
    )
    fn: float | None = Field(
        None,
        ge=MIN_FORCE,
        le=MAX_FORCE,
        allow_inf_nan=False,
        description=f"F_n, resistance against the grain, N (default {DEFAULT_FN_OVER_FP:g} F_p)",
    )
    k: float = Field(
        PAPER_K, ge=1e-9, le=1e9, allow_inf_nan=False, description="bristle stiffness, N/mm"
    )
    length: float = Field(
        PAPER_LENGTH,
        ge=1e-3,
        le=MAX_LENGTH,
        allow_inf_nan=False,
        description="distance between first and last bristle, mm",
    )
    cycles: int = Field(PAPER_CYCLES, ge=1, le=100_000, description="number of strokes")
    period: float = Field(
        PAPER_PERIOD, ge=1e-6, le=1e7, allow_inf_nan=False, description="stroke period T, s"
    )
    bristles: int = Field(2, ge=2, le=10_000, description="number of bristles N")
    gait: Literal["breathing", "peristaltic"] = "breathing"
    lag: float | None = Field(
        None,
        ge=-1e7,
        le=1e7,
        allow_inf_nan=False,
        description="peristaltic delay between neighbouring segments, s (default period / 4)",
    )
    stroke: Literal["sin2", "triangle"] = "sin2"
    actuator: Literal["sin2", "sma"] = Field(
        "sin2",
        description="prescribed stroke, or the closed-loop SMA actuator model with "
        "target s_max (then period is not used)",
    )
    history: str | None = Field(None, description="CSV file with columns t (s) and s (mm)")
    texture: str | None = Field(
        None,
        description="a drag test's summary.json: the crawler on its texture law (k, F_p(x), "
        "F_n(x) over a pitch); fp, fn and k are then not used",
    )
    samples_per_cycle: int = Field(
        2000, ge=2, le=10_000_000, description="samples per period of an analytic stroke"
    )

    @model_validator(mode="after")
    def _consistent(self) -> ReducedConfig:
        c = self.fp / self.k
        if not MIN_FP_OVER_K <= c <= MAX_LENGTH:
            raise ValueError(
                f"fp / k ({c:g} mm, the bristle's deflection at sliding) must be within "
                f"[{MIN_FP_OVER_K:g}, {MAX_LENGTH:g}] mm"
            )
        if self.cycles * self.samples_per_cycle > MAX_SAMPLES:
            raise ValueError(
                f"cycles x samples_per_cycle ({self.cycles * self.samples_per_cycle:g}) must "
                f"be at most {MAX_SAMPLES:g} samples"
            )
        if self.history is not None and self.actuator == "sma":
            raise ValueError("give either a history file or actuator = 'sma', not both")
        fn = np.nan if self.fn is None else self.fn
        found = first_inconsistency(
            self.fp, fn, self.s_max, self.length, self.bristles, self.history is not None
        )
        if found is not None:
            raise ValueError(found[1])
        return self

    @property
    def fn_resolved(self) -> float:
        return self.fn if self.fn is not None else DEFAULT_FN_OVER_FP * self.fp

    @property
    def lag_resolved(self) -> float:
        return self.lag if self.lag is not None else self.period / 4


def first_inconsistency(fp, fn, s_max, length, bristles, history: bool = False):
    """The first of a batch of configurations whose values contradict each other, as
    ``(index, message)`` (index into the broadcast, flattened arrays), or None.

    Vectorised so that a design study checks millions of designs at once; fn = NaN stands
    for the default F_n. ``history``: the stroke comes from a file (no bound on s_max here).
    """
    fp, fn, s_max, length, bristles = (
        a.ravel()
        for a in np.broadcast_arrays(
            *(np.asarray(v, float) for v in (fp, fn, s_max, length, bristles))
        )
    )
    fn = np.where(np.isnan(fn), DEFAULT_FN_OVER_FP * fp, fn)
    bad = fn < fp
    if bad.any():
        i = int(np.argmax(bad))
        return i, f"fn ({fn[i]:g} N) must be >= fp ({fp[i]:g} N)"
    if history:
        return None
    seg = length / (bristles - 1)
    bad = s_max >= seg
    if bad.any():
        i = int(np.argmax(bad))
        what = "length L" if bristles[i] == 2 else f"segment length L/(N-1) = {seg[i]:g} mm"
        return i, f"s_max ({s_max[i]:g} mm) must be smaller than the {what}"
    return None


def read_texture(path: str | Path):
    """The :class:`TextureLaw` in a drag test's ``summary.json`` (key ``texture``) or in a
    JSON file holding the law itself; InputError (one line) otherwise."""
    import json

    from bristlecrawler._files import MAX_SMALL_BYTES, read_bytes
    from bristlecrawler.errors import InputError
    from bristlecrawler.results.texture import TextureLaw

    try:
        data = json.loads(read_bytes(path, MAX_SMALL_BYTES))
    except FileNotFoundError:
        raise InputError(f"texture file not found: {path}") from None
    except OSError as err:
        raise InputError(f"texture {path}: cannot read it ({err.strerror or err})") from None
    except (ValueError, RecursionError) as err:
        raise InputError(f"texture {path}: not a JSON file ({err})"[:300]) from None
    law = data.get("texture", data) if isinstance(data, dict) else None
    if not isinstance(law, dict):
        raise InputError(f"texture {path}: no texture law (run a drag test with direction cycle)")
    return TextureLaw.from_dict(law)


def build(config: ReducedConfig):
    """Crawler and gait described by ``config`` (reads the history and texture files)."""
    if config.texture is not None:
        from bristlecrawler.reduced.textured import TexturedCrawler

        law = read_texture(config.texture)
        crawler = TexturedCrawler.uniform(law, config.bristles, config.length)
    else:
        crawler = ReducedCrawler.uniform(
            config.bristles, config.length, config.k, config.fp, config.fn_resolved
        )
    if config.history is not None:
        stroke = read_history_csv(config.history)
        crawler.check_stroke(stroke.s_max)
    elif config.actuator == "sma":
        from bristlecrawler.actuators.sma import SMAActuator, run_sma

        stroke = run_sma(SMAActuator(s_target=config.s_max), config.cycles).stroke()
        crawler.check_stroke(stroke.s_max)
    else:
        cls = Sin2Stroke if config.stroke == "sin2" else TriangleStroke
        stroke = cls(config.s_max, config.period)
    nseg = config.bristles - 1
    if config.gait == "peristaltic":
        gait = peristaltic(stroke, nseg, config.lag_resolved)
    else:
        gait = breathing(stroke, nseg)
    return crawler, gait
