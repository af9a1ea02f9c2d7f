"""Input decks for ABAQUS and CalculiX from a :class:`~bristlecrawler.crawler.CrawlerSpec`.

The paper's FE model is an ABAQUS model; these decks put a design of this toolkit in the
form ABAQUS (and, for the continuum drag test, CalculiX) reads, so that another FE code
can check a result:

* ``drag_continuum.inp``: the drag test of one bristle, the bristle plane-stress or
  plane-strain quadrilaterals, the substrate a fixed layer of elements; ABAQUS and
  CalculiX (:func:`continuum_deck`).
* ``drag_beam.inp``: the same test with the paper's B21 beams and an analytical rigid
  surface; ABAQUS only (:func:`drag_beam_deck`).
* ``crawler.inp``: the whole crawler as in the paper, ABAQUS only (:func:`crawler_deck`).
* ``README.md``: what each deck holds and which keywords CalculiX runs.

:func:`write_decks` writes them all into a folder; :mod:`.crosscheck` runs CalculiX on
the drag test and compares it with the toolkit's own.
"""

from __future__ import annotations

from pathlib import Path

from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.export.beam import drag_beam_deck
from bristlecrawler.export.crawler_deck import crawler_deck
from bristlecrawler.export.drag_deck import ContinuumOptions, continuum_deck, crosscheck_spec
from bristlecrawler.export.readme import readme
from bristlecrawler.export.results import read_dat

#: The files :func:`write_decks` writes.
DECK_FILES = ("drag_continuum.inp", "drag_beam.inp", "crawler.inp", "README.md")


def decks(
    spec: CrawlerSpec,
    test: DragTest | None = None,
    options: ContinuumOptions | None = None,
    a0: float | None = None,
) -> dict[str, str]:
    """Every deck of ``spec`` and its README, by file name (checked and built in memory:
    a spec the decks cannot express raises :class:`InputError` before anything is written)."""
    test = test or DragTest()
    cont, cont_info = continuum_deck(spec, test, options)
    beam, _ = drag_beam_deck(spec, test, a0)
    crawler, crawler_info = crawler_deck(spec, a0)
    text = readme(spec, test, options or ContinuumOptions(), cont_info, crawler_info)
    return dict(zip(DECK_FILES, (cont, beam, crawler, text), strict=True))


def write_decks(folder: str | Path, texts: dict[str, str]) -> list[Path]:
    """Write ``texts`` (from :func:`decks`) into ``folder``; returns the paths."""
    folder = Path(folder)
    out = []
    for name, text in texts.items():
        path = folder / name
        path.write_text(text, encoding="ascii")
        out.append(path)
    return out


__all__ = [
    "DECK_FILES",
    "ContinuumOptions",
    "continuum_deck",
    "crawler_deck",
    "crosscheck_spec",
    "decks",
    "drag_beam_deck",
    "read_dat",
    "write_decks",
]
