"""A writer for input decks in the ABAQUS keyword dialect (which CalculiX also reads).

A :class:`Deck` collects keyword lines; numbers are written with 12 significant digits,
data lines hold at most 16 entries (the dialect's limit), and names are checked against
the dialect's rules (a letter first, then letters, digits and underscores, at most 80
characters), so a deck is valid by construction rather than by inspection.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence

import numpy as np

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,79}$")


def number(v: float) -> str:
    """A number as the deck writes it: an integer as is, a float with 12 digits."""
    if isinstance(v, int | np.integer):
        return str(int(v))
    v = float(v)
    if not np.isfinite(v):
        raise ValueError(f"a deck holds finite numbers only, got {v}")
    text = f"{v:.12g}"
    return text if any(c in text for c in ".eE") else text + "."


def name(text: str) -> str:
    """``text`` if it is a valid set, surface or material name; ValueError otherwise."""
    if not _NAME.match(text):
        raise ValueError(f"{text!r} is not a valid deck name")
    return text.upper()


class Deck:
    """Lines of an input deck, written in order."""

    def __init__(self, heading: str) -> None:
        self.lines: list[str] = ["*HEADING", *heading.strip().splitlines()]

    def comment(self, text: str) -> None:
        self.lines += [f"** {line}".rstrip() for line in text.strip().splitlines()]

    def keyword(self, word: str, **params) -> None:
        """``*WORD, KEY=VALUE, FLAG`` (a parameter given as True is a flag)."""
        parts = [f"*{word.upper()}"]
        for key, value in params.items():
            key = key.upper().replace("_", " ")
            if value is True:
                parts.append(key)
            elif value is not None and value is not False:
                parts.append(f"{key}={value}")
        self.lines.append(", ".join(parts))

    def data(self, *values) -> None:
        """One data line (numbers and words)."""
        if len(values) > 16:
            raise ValueError("a data line holds at most 16 entries")
        self.lines.append(", ".join(v if isinstance(v, str) else number(v) for v in values))

    def rows(self, rows: Iterable[Sequence]) -> None:
        for row in rows:
            self.data(*row)

    def nodes(self, first: int, points: np.ndarray, nset: str | None = None) -> np.ndarray:
        """Nodes numbered from ``first`` at ``points`` (K, 2), z = 0; returns their labels."""
        self.keyword("NODE", nset=nset and name(nset))
        labels = first + np.arange(len(points))
        for label, (x, y) in zip(labels, points, strict=True):
            self.data(int(label), float(x), float(y), 0.0)
        return labels

    def elements(self, kind: str, first: int, conn: np.ndarray, elset: str) -> np.ndarray:
        """Elements of type ``kind`` numbered from ``first``; ``conn`` holds node labels."""
        self.keyword("ELEMENT", type=kind, elset=name(elset))
        labels = first + np.arange(len(conn))
        for label, row in zip(labels, conn, strict=True):
            self.data(int(label), *(int(n) for n in row))
        return labels

    def labels(self, word: str, set_name: str, labels: Iterable[int]) -> None:
        """``*NSET`` or ``*ELSET`` with 16 labels a line."""
        self.keyword(word, **{word.lower(): name(set_name)})
        items = [int(v) for v in labels]
        for i in range(0, len(items), 16):
            self.data(*items[i : i + 16])

    def text(self) -> str:
        return "\n".join(self.lines) + "\n"
