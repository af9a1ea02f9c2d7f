"""Scenarios of the finite-element crawler model: TOML files validated by pydantic.

``load_scenario("paper")`` loads a shipped scenario (``paper``: alpha = pi/4,
``paper-vertical``: alpha = 0); ``load_scenario("my.toml")`` a file. Every value has a unit
in its field description and defaults to the paper's.
"""

from bristlecrawler.scenario.load import available_scenarios, load_scenario, scenario_from_dict
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
    "available_scenarios",
    "load_scenario",
    "scenario_from_dict",
]
