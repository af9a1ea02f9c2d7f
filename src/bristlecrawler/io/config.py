"""Validation of user input with pydantic, turned into one-line :class:`InputError` messages."""

from __future__ import annotations

from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from bristlecrawler.errors import InputError

M = TypeVar("M", bound=BaseModel)


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
