"""A reader of the ABAQUS keyword dialect, independent of the writer, for the tests."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Block:
    keyword: str
    params: dict[str, str]
    rows: list[list[str]] = field(default_factory=list)

    def numbers(self) -> list[list[float]]:
        return [[float(v) for v in row] for row in self.rows]


def parse(text: str) -> list[Block]:
    """Keyword blocks in order; comment lines (``**``) skipped; every data line must follow a
    keyword and hold at most 16 entries."""
    blocks: list[Block] = []
    for line in text.splitlines():
        if line.startswith("**") or not line.strip():
            continue
        if line.startswith("*"):
            head, *rest = [p.strip() for p in line[1:].split(",")]
            params = {}
            for p in rest:
                key, _, value = p.partition("=")
                params[key.strip().upper()] = value.strip()
            blocks.append(Block(head.upper(), params))
            continue
        assert blocks, f"data line before any keyword: {line!r}"
        row = [v.strip() for v in line.split(",")]
        assert len(row) <= 16, f"more than 16 entries: {line!r}"
        blocks[-1].rows.append(row)
    return blocks


def find(blocks: list[Block], keyword: str, **params) -> list[Block]:
    out = []
    for b in blocks:
        if b.keyword != keyword:
            continue
        if all(b.params.get(k.upper().replace("_", " ")) == v for k, v in params.items()):
            out.append(b)
    return out


def nodes(blocks: list[Block]) -> dict[int, tuple[float, float]]:
    out = {}
    for b in find(blocks, "NODE"):
        for row in b.numbers():
            out[int(row[0])] = (row[1], row[2])
    return out


def elements(blocks: list[Block], kind: str) -> dict[int, list[int]]:
    out = {}
    for b in find(blocks, "ELEMENT", type=kind):
        for row in b.rows:
            out[int(row[0])] = [int(v) for v in row[1:]]
    return out


def amplitude(blocks: list[Block], name: str):
    (b,) = find(blocks, "AMPLITUDE", name=name)
    flat = [v for row in b.numbers() for v in row]
    return flat[0::2], flat[1::2]
