"""Command-line interface (Typer). Entry point: :func:`bristlecrawler.cli.app.main`."""
