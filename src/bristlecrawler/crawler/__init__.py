"""The finite-element bristle crawler (paper Section 3): model, run, and its record."""

from bristlecrawler.crawler.history import TIP_OPEN, TIP_SLIP, TIP_STICK, CrawlerHistory

__all__ = ["TIP_OPEN", "TIP_SLIP", "TIP_STICK", "CrawlerHistory"]
