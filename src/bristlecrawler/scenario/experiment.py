"""Options of the experiment commands (``analyze``, ``synth-recording``), validated by
pydantic at the edge with physical bounds."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field


class AnalyzeOptions(BaseModel):
    """Numbers of ``bristlecrawler analyze`` that are not in the recording."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    work: float | None = Field(
        None,
        gt=0,
        le=1e6,
        allow_inf_nan=False,
        description="actuator work over the analysed cycles, mJ (up to 1e6)",
    )
    rate: float = Field(
        100.0,
        gt=0,
        le=1e7,
        allow_inf_nan=False,
        description="sample rate without a time column, samples/s (up to 1e7)",
    )
    max_gap: float = Field(
        0.5, gt=0, le=1e4, allow_inf_nan=False, description="longest dropout bridged, s"
    )


class SynthOptions(BaseModel):
    """Parameters of ``bristlecrawler synth-recording``."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    actuator: Literal["sma", "sin2"] = "sma"
    cycles: int = Field(5, ge=1, le=1000, description="number of cycles")
    fp: float = Field(
        0.456, ge=1e-6, le=1e3, allow_inf_nan=False, description="F_p, N (1e-6 to 1e3)"
    )
    k: float = Field(
        0.48, ge=1e-6, le=1e6, allow_inf_nan=False, description="bristle stiffness, N/mm"
    )
    noise: float = Field(
        0.01, ge=0, le=100, allow_inf_nan=False, description="sensor noise (std), mm"
    )
    skip: float = Field(
        0.0, ge=0, le=1e5, allow_inf_nan=False, description="seconds cut from the start"
    )
    seed: int = Field(0, ge=0, le=2**63 - 1, description="random seed (>= 0)")
