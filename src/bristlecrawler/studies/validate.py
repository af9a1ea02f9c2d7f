"""Every design is checked against the model's schema before any work starts; the first
one that fails is named with its values in a one-line :class:`InputError`."""

from __future__ import annotations

from typing import Annotated

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.studies.designs import Base, Designs, with_overrides

# Up to this many designs each one goes through the full schema; beyond, each axis's
# values are checked against their field and the cross-field rules run vectorised.
FULL_CHECK = 20_000


def validate_designs(base: Base, designs: Designs) -> None:
    """InputError naming the first design that the model's schema refuses."""
    if base.model == "fe":
        _validate_fe(base, designs)
    else:
        _validate_reduced(base, designs)


def _validate_fe(base: Base, designs: Designs) -> None:
    from bristlecrawler.scenario.load import scenario_from_dict

    for i in range(designs.n):
        data = with_overrides(base.config, designs.overrides(i))
        try:
            scenario_from_dict(data, "scenario")
        except InputError as exc:
            message = str(exc).removeprefix("scenario: ")
            raise InputError(f"{designs.label(i)}: {message}") from None


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
