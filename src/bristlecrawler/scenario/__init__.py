"""Scenarios of the finite-element crawler model: TOML files validated by pydantic.

``load_scenario("paper")`` loads a shipped scenario (``paper``: alpha = pi/4,
``paper-vertical``: alpha = 0); ``load_scenario("my.toml")`` a file. Every value has a unit
in its field description and defaults to the paper's. ``load_spec`` and ``to_spec`` give
the plain :class:`bristlecrawler.crawler.CrawlerSpec` the FE crawler runs.
"""

from bristlecrawler.scenario.convert import load_spec, to_spec
from bristlecrawler.scenario.load import (
    apply_overrides,
    apply_values,
    available_scenarios,
    load_scenario,
    scenario_from_dict,
)
from bristlecrawler.scenario.schema import (
    ActuationConfig,
    BodyConfig,
    BristleConfig,
    DampingConfig,
    OutputConfig,
    Scenario,
    SolverConfig,
)

__all__ = [
    "ActuationConfig",
    "BodyConfig",
    "BristleConfig",
    "DampingConfig",
    "OutputConfig",
    "Scenario",
    "SolverConfig",
    "apply_overrides",
    "apply_values",
    "available_scenarios",
    "load_scenario",
    "load_spec",
    "scenario_from_dict",
    "to_spec",
]
