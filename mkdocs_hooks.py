"""MkDocs hook: reference tables are generated from the code at build time.

A page with the line ``<!-- scenario-keys -->`` gets the tables of
``bristlecrawler scenario keys --markdown`` in its place, and one with
``<!-- crawler-variables -->`` the table of ``crawler.nc``'s variables from their
declarations (``bristlecrawler.crawler.quantities``), and one with
``<!-- reduced-variables -->`` that of ``reduced.nc``'s
(``bristlecrawler.io.netcdf.REDUCED_VARIABLES``), so the references cannot drift from
the code.
"""

from __future__ import annotations

MARKER = "<!-- scenario-keys -->"
CRAWLER_VARIABLES = "<!-- crawler-variables -->"
REDUCED_VARIABLES = "<!-- reduced-variables -->"


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
    return markdown
