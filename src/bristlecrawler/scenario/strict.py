"""Validation of user input with pydantic, turned into one-line :class:`InputError` messages."""

from __future__ import annotations

from typing import Any, TypeVar

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator

from bristlecrawler.errors import InputError

M = TypeVar("M", bound=BaseModel)


class StrictSection(BaseModel):
    """A table of a configuration file: unknown keys refused, frozen, and strict: a number
    must be a number (TOML 45 or 45.0), not a bool or the string "45" (lax mode would take
    ``--set bristle.elements=true`` as one element). A numpy scalar (a sweep's
    ``np.linspace`` value) is taken as its Python number."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    @model_validator(mode="before")
    @classmethod
    def _plain_numbers(cls, data):
        if isinstance(data, dict):
            return {k: v.item() if isinstance(v, np.generic) else v for k, v in data.items()}
        return data


def first_error_message(exc: ValidationError) -> str:
    """One line: the first problem, naming the parameter."""
    err = exc.errors()[0]
    loc = ".".join(str(p) for p in err.get("loc", ()) if p != "__root__")
    msg = str(err.get("msg", "invalid value"))
    msg = msg.removeprefix("Value error, ")
    where = f"{loc}: " if loc else ""
    extra = f" (and {len(exc.errors()) - 1} more problems)" if len(exc.errors()) > 1 else ""
    return f"{where}{msg}{extra}"


def parse_model(model: type[M], data: dict[str, Any]) -> M:
    """Validate ``data`` into ``model``; raise :class:`InputError` with one line on failure."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        raise InputError(first_error_message(exc)) from None
