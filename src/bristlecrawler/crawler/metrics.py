"""An FE crawler run's metrics as the typed results every model shares
(:mod:`bristlecrawler.results.metrics`)."""

from __future__ import annotations

from bristlecrawler.results.metrics import RunMetrics


def run_metrics(history) -> RunMetrics:
    """Net advance (mm), advance of each cycle (mm) and connector work (mJ) of a
    :class:`~bristlecrawler.crawler.history.CrawlerHistory`."""
    return RunMetrics(
        float(history.net_advance),
        tuple(float(a) for a in history.advance_per_cycle()),
        float(history.connector_work[-1]),
    )
