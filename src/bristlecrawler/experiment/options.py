"""The experiment commands' settings, each declared once (default, meaning with its unit,
range): what ``bristlecrawler analyze`` needs beyond the recording, and what
``bristlecrawler synth-recording`` makes. The commands' option tables are generated from
these declarations (:mod:`bristlecrawler.scenario.experiment`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from bristlecrawler.experiment.recording import DEFAULT_RATE_HZ, Recording
from bristlecrawler.experiment.synthetic import SensorModel, synthetic_recording
from bristlecrawler.reduced.crawler import PAPER_CYCLES, PAPER_K, ReducedCrawler
from bristlecrawler.settings import Settings, setting


@dataclass(frozen=True)
class AnalysisOptions(Settings):
    """What an analysis of a recording needs beyond the recording (:func:`analyze`)."""

    work: float | None = setting(
        None,
        "actuator work over the analysed cycles, mJ; None: F_p and k from the force channel "
        "if the recording has one",
        gt=0,
        le=1e6,
        none=True,
    )
    rate: float = setting(
        DEFAULT_RATE_HZ, "sample rate without a time column, samples/s", gt=0, le=1e7
    )
    max_gap: float = setting(0.5, "longest dropout bridged, s", gt=0, le=1e4)


@dataclass(frozen=True)
class SynthesisOptions(Settings):
    """A synthetic recording of the paper's two-bristle crawler (:func:`synthetic_recording`)
    with the sensor's artefacts (:class:`SensorModel`)."""

    actuator: Literal["sma", "sin2"] = setting(
        "sma",
        "actuator model; sma: the closed-loop shape-memory-alloy model, sin2: the prescribed "
        "sin^2 stroke",
    )
    cycles: int = setting(PAPER_CYCLES, "number of cycles", ge=1, le=1000)
    fp: float = setting(0.456, "F_p, resistance along the grain, N", ge=1e-6, le=1e3)
    k: float = setting(PAPER_K, "bristle stiffness, N/mm", ge=1e-6, le=1e6)
    noise: float = setting(
        SensorModel.noise_mm, "sensor noise (standard deviation), mm", ge=0, le=100
    )
    skip: float = setting(SensorModel.skip_s, "time cut from the start, s", ge=0, le=1e5)
    seed: int = setting(0, "random seed", ge=0, le=2**63 - 1)

    def recording(self) -> Recording:
        """The synthetic recording these settings describe."""
        return synthetic_recording(
            ReducedCrawler.two_bristle(fp=self.fp, k=self.k),
            actuator=self.actuator,
            cycles=self.cycles,
            sensor=SensorModel(noise_mm=self.noise, skip_s=self.skip),
            seed=self.seed,
        )
