"""Actuator models that drive a crawler's shortening: the SMA spring with antagonist bands.

Used by the FE crawler (a scenario's ``actuation.kind = "sma"``), the reduced model and the
experiment side alike, so it depends on none of them.
"""

from bristlecrawler.actuators.sma import SMAActuator, SMAResponse, run_sma

__all__ = ["SMAActuator", "SMAResponse", "run_sma"]
