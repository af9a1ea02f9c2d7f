"""Options of the experiment commands (``analyze``, ``synth-recording``), validated by
pydantic at the edge: tables generated from the settings
:mod:`bristlecrawler.experiment.options` declares."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from bristlecrawler.experiment.options import AnalysisOptions, SynthesisOptions
from bristlecrawler.scenario.strict import section_of


class _Options(BaseModel):
    """A command's options: unknown keys refused, frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


#: Numbers of ``bristlecrawler analyze`` that are not in the recording.
AnalyzeOptions = section_of(
    AnalysisOptions,
    _Options,
    "Numbers of ``bristlecrawler analyze`` that are not in the recording.",
    name="AnalyzeOptions",
)

#: Parameters of ``bristlecrawler synth-recording``.
SynthOptions = section_of(
    SynthesisOptions,
    _Options,
    "Parameters of ``bristlecrawler synth-recording``.",
    name="SynthOptions",
)
