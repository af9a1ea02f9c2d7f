"""MkDocs hook: reference tables are generated from the code at build time.

A page with the line ``<!-- scenario-keys -->`` gets the tables of
``bristlecrawler scenario keys --markdown`` in its place, and one with
``<!-- crawler-variables -->`` the table of ``crawler.nc``'s variables from their
declarations (``bristlecrawler.crawler.quantities``), and one with
``<!-- reduced-variables -->`` that of ``reduced.nc``'s
(``bristlecrawler.io.netcdf.REDUCED_VARIABLES``), and one with ``<!-- drag-variables -->``
that of ``drag.nc``'s (``bristlecrawler.crawler.drag_analysis.DRAG_VARIABLES``), and a
line ``<!-- options: COMMAND -->`` the table of a command's declared options
(``bristlecrawler.scenario.keys.options_markdown``), so the references cannot drift from
the code.
"""

from __future__ import annotations

import re

MARKER = "<!-- scenario-keys -->"
CRAWLER_VARIABLES = "<!-- crawler-variables -->"
REDUCED_VARIABLES = "<!-- reduced-variables -->"
DRAG_VARIABLES = "<!-- drag-variables -->"
OPTIONS = re.compile(r"^<!-- options: ([a-z-]+) -->$", re.M)


def on_page_markdown(markdown: str, page, config, files) -> str:
    if MARKER in markdown:
        from bristlecrawler.scenario.keys import keys_markdown

        markdown = markdown.replace(MARKER, keys_markdown())
    if CRAWLER_VARIABLES in markdown:
        from bristlecrawler.crawler.quantities import quantities_markdown

        markdown = markdown.replace(CRAWLER_VARIABLES, quantities_markdown())
    if REDUCED_VARIABLES in markdown:
        from bristlecrawler.io.netcdf import reduced_variables_markdown

        markdown = markdown.replace(REDUCED_VARIABLES, reduced_variables_markdown())
    if DRAG_VARIABLES in markdown:
        from bristlecrawler.crawler.drag_analysis import drag_variables_markdown

        markdown = markdown.replace(DRAG_VARIABLES, drag_variables_markdown())
    if OPTIONS.search(markdown):
        from bristlecrawler.scenario.keys import options_markdown

        markdown = OPTIONS.sub(lambda m: options_markdown(m.group(1)), markdown)
    return markdown
