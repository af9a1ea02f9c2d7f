"""Every design is checked against the model's schema before any work starts; the first
one that fails is named with its values in a one-line :class:`InputError`.

An FE design takes about 1.4 ms to check: beyond :data:`FE_FULL_CHECK` designs, the first
ones, every value of every axis (up to 500 spread over a long axis) and the corners of the
grid are checked, so that a study of millions starts within seconds; a design left
unchecked that the schema refuses is recorded as failed, with the schema's message."""

from __future__ import annotations

from typing import Annotated

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.studies.designs import Base, Designs, with_overrides

# Up to this many designs each one goes through the full schema; beyond, each axis's
# values are checked against their field and the cross-field rules run vectorised.
FULL_CHECK = 20_000
FE_FULL_CHECK = 2_000


def validate_designs(base: Base, designs: Designs) -> None:
    """InputError naming the first design that the model's schema refuses, or whose
    texture or history file cannot be read."""
    if base.model == "fe":
        _validate_fe(base, designs)
    else:
        _validate_reduced(base, designs)
    check_files(base, designs)


def check_files(base: Base, designs: Designs) -> None:
    """Read and check every distinct texture and history file the designs name, before
    the first design starts: a missing, unreadable or malformed one (a FIFO, a device)
    is one InputError, not a study whose every design fails."""
    from bristlecrawler.reduced.strokes import read_history_csv
    from bristlecrawler.scenario.reduced import read_texture

    if base.model == "fe":
        act = base.config.get("actuation", {})
        readers = {"actuation.history": (read_history_csv, act.get("history"))}
    else:
        readers = {
            "texture": (read_texture, base.config.get("texture")),
            "history": (read_history_csv, base.config.get("history")),
        }
    for key, (read, value) in readers.items():
        if key in designs.keys:
            seen: set[str] = set()
            for i, v in enumerate(designs.values[key].tolist()):
                if isinstance(v, str) and v not in seen:
                    seen.add(v)
                    _read(read, v, designs.label(i))
        elif isinstance(value, str) and value:
            _read(read, value, f"[set] {key}" if key else "base")


def _read(read, path: str, where: str) -> None:
    try:
        read(path)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


def _validate_fe(base: Base, designs: Designs) -> None:
    from bristlecrawler.scenario.load import scenario_from_dict

    for i in _fe_probe(designs):
        data = with_overrides(base.config, designs.overrides(i))
        try:
            scenario_from_dict(data, "scenario")
        except InputError as exc:
            message = str(exc).removeprefix("scenario: ")
            raise InputError(f"{designs.label(i)}: {message}") from None


def _fe_probe(designs: Designs) -> list[int]:
    """The designs checked (see the module): all of them up to FE_FULL_CHECK."""
    import itertools

    n, shape = designs.n, designs.shape
    if n <= FE_FULL_CHECK:
        return list(range(n))
    picks = set(range(FE_FULL_CHECK // 2))
    for axis, size in enumerate(shape):
        for j in np.unique(np.linspace(0, size - 1, min(size, 500)).astype(np.int64)):
            at = [0] * len(shape)
            at[axis] = int(j)
            picks.add(int(np.ravel_multi_index(at, shape)))
    corners = itertools.product(*[(0, s - 1) for s in shape])
    picks |= {int(np.ravel_multi_index(c, shape)) for c in itertools.islice(corners, 1024)}
    return sorted(picks)


def _validate_reduced(base: Base, designs: Designs) -> None:
    from pydantic import TypeAdapter, ValidationError

    from bristlecrawler.scenario.reduced import ReducedConfig, first_inconsistency
    from bristlecrawler.scenario.strict import first_error_message, parse_model

    if designs.n <= FULL_CHECK:
        for i in range(designs.n):
            try:
                parse_model(ReducedConfig, base.config | designs.overrides(i))
            except InputError as exc:
                raise InputError(f"{designs.label(i)}: {exc}") from None
        return
    for key in designs.keys:
        field = ReducedConfig.model_fields[key]
        adapter = TypeAdapter(Annotated[field.annotation, field])
        _dim, axis = designs.coords[key]
        probe = np.unique(axis) if axis.size <= 1000 else np.array([axis.min(), axis.max()])
        for value in probe:
            try:
                adapter.validate_python(value.item())
            except ValidationError as exc:
                i = int(np.argmax(designs.values[key] == value))
                raise InputError(f"{designs.label(i)}: {key}: {first_error_message(exc)}") from None

    def col(key):
        v = designs.values.get(key, base.config[key])
        return np.nan if v is None else v

    found = first_inconsistency(
        col("fp"),
        col("fn"),
        col("s_max"),
        col("length"),
        col("bristles"),
        base.config["history"] is not None,
    )
    if found is not None:
        i, message = found
        raise InputError(f"{designs.label(i)}: {message}")
    # Anything else (a rule between non-numeric options) shows on the first design.
    parse_model(ReducedConfig, base.config | designs.overrides(0))
