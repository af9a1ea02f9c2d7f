"""Command groups whose listings show each command's whole first sentence."""

from __future__ import annotations

from typer.core import TyperGroup


class WholeSummaries(TyperGroup):
    """A group that lists each command with its help's whole first sentence (click cuts a
    summary at a width of its own, even on a wide terminal)."""

    def __init__(self, **attrs) -> None:
        super().__init__(**attrs)
        for cmd in self.commands.values():
            if not cmd.short_help and cmd.help:
                cmd.short_help = cmd.get_short_help_str(limit=10_000)
