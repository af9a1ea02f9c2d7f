"""From a validated :class:`Scenario` (the TOML edge) to the plain :class:`CrawlerSpec`."""

from __future__ import annotations

import dataclasses
import os

import numpy as np

from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.scenario.schema import Scenario


def _history(sc: Scenario) -> tuple[tuple[float, ...], tuple[float, ...]] | None:
    """The sampled stroke of a ``history`` or ``sma`` actuation (times from 0), or None."""
    a = sc.actuation
    if a.kind == "sin2":
        return None
    if a.kind == "history":
        from bristlecrawler.reduced.strokes import read_history_csv

        st = read_history_csv(a.history)
    else:
        from bristlecrawler.actuators.sma import SMAActuator, run_sma

        st = run_sma(SMAActuator(s_target=a.s_max), a.cycles).stroke()
    t, s = np.asarray(st.t, dtype=float), np.asarray(st.s, dtype=float)
    return tuple((t - t[0]).tolist()), tuple(s.tolist())


def to_spec(sc: Scenario) -> CrawlerSpec:
    """The :class:`CrawlerSpec` of a validated scenario (reads a history file, runs the SMA
    actuator model for ``kind = "sma"``); raises a one-line InputError for a stroke the
    design cannot make (the scenario's validation checked the rest)."""
    spec = sc.design()
    history = _history(sc)
    if history is None:
        return spec
    spec = dataclasses.replace(spec, actuation=dataclasses.replace(spec.actuation, history=history))
    spec.actuation.rules()
    spec.check_stroke()
    return spec


def load_spec(name_or_path: str | os.PathLike, overrides: list[str] | None = None) -> CrawlerSpec:
    """The spec of a shipped scenario (``paper``, ``paper-vertical``) or a TOML file, with
    ``section.key=value`` overrides (TOML values) applied first."""
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    sc = load_scenario(name_or_path)
    if overrides:
        sc = apply_overrides(sc, overrides)
    return to_spec(sc)
