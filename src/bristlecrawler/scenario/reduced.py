"""The reduced-model run configuration (CLI options or a TOML table), validated by pydantic,
and the crawler and gait it describes (:func:`build`)."""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel, ConfigDict

from bristlecrawler.reduced.run import (
    MAX_FORCE,
    MAX_LENGTH,
    MAX_SAMPLES,
    MIN_FORCE,
    MIN_FP_OVER_K,
    ReducedRun,
    first_inconsistency,
)
from bristlecrawler.reduced.strokes import read_history_csv
from bristlecrawler.scenario.strict import section_of

__all__ = [
    "MAX_FORCE",
    "MAX_LENGTH",
    "MAX_SAMPLES",
    "MIN_FORCE",
    "MIN_FP_OVER_K",
    "ReducedConfig",
    "build",
    "first_inconsistency",
    "read_texture",
]


class _ReducedTable(BaseModel):
    """Options of a reduced-model run: unknown keys refused, frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    def run(self) -> ReducedRun:
        """The :class:`ReducedRun` these options describe."""
        return ReducedRun(**self.model_dump())

    @property
    def fn_resolved(self) -> float:
        return self.run().fn_resolved

    @property
    def lag_resolved(self) -> float:
        return self.run().lag_resolved


#: The options of ``bristlecrawler reduced`` and of a reduced design study's base:
#: :class:`~bristlecrawler.reduced.run.ReducedRun`'s settings, whose ``rules`` run after
#: the ranges.
ReducedConfig = section_of(
    ReducedRun,
    _ReducedTable,
    "Parameters of a reduced-model run. Defaults reproduce the paper (Section 4).",
    name="ReducedConfig",
)


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


def build(config):
    """Crawler and gait described by ``config`` (a :class:`ReducedConfig` or a
    :class:`ReducedRun`; reads the history and texture files)."""
    run = ReducedRun(**config.model_dump()) if isinstance(config, BaseModel) else config
    if run.texture is not None:
        from bristlecrawler.reduced.textured import TexturedCrawler

        law = read_texture(run.texture)
        crawler = TexturedCrawler.uniform(law, run.bristles, run.length)
    else:
        crawler = run.crawler()
    if run.history is not None:
        stroke = read_history_csv(run.history)
        crawler.check_stroke(stroke.s_max)
    elif run.actuator == "sma":
        from bristlecrawler.actuators.sma import SMAActuator, run_sma

        stroke = run_sma(SMAActuator(s_target=run.s_max), run.cycles).stroke()
        crawler.check_stroke(stroke.s_max)
    else:
        stroke = run.analytic_stroke()
    return crawler, run.gait_of(stroke)
