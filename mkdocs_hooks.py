"""MkDocs hook: the scenario reference is generated from the schema at build time.

A page with the line ``<!-- scenario-keys -->`` gets the tables of
``bristlecrawler scenario keys --markdown`` in its place, so the reference cannot drift
from the code.
"""

from __future__ import annotations

MARKER = "<!-- scenario-keys -->"


def on_page_markdown(markdown: str, page, config, files) -> str:
    if MARKER not in markdown:
        return markdown
    from bristlecrawler.scenario.keys import keys_markdown

    return markdown.replace(MARKER, keys_markdown())
