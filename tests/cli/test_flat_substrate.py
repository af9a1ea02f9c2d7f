"""A shipped scenario switched to a flat substrate runs with its contact settings as they
are: corner contact (on in `paper`) acts on the substrate's convex corners where it has
any, and a plane has none."""

import pytest


class _Built(Exception):
    """Raised by the solver's stand-in once the command has built its model."""


@pytest.mark.parametrize("command", ["drag", "simulate"])
def test_a_flat_substrate_runs_with_corner_contact_left_on(command, run_cli, tmp_path, monkeypatch):
    # The solver's stand-in stops the run once the command has built its model: the
    # point contact alone, no corner term.
    from bristlecrawler.contact.term import SubstrateContact

    built = []

    def stand_in(crawler, stages, options=None, on_progress=None):
        built.append([type(t) for t in crawler.model.terms])
        raise _Built

    # The drag test holds its own name for the runner's function once imported.
    monkeypatch.setattr("bristlecrawler.crawler.runner.run_stages", stand_in)
    monkeypatch.setattr("bristlecrawler.crawler.drag.run_stages", stand_in)
    args = [command, "paper", "--set", "substrate.kind=flat", "--out", str(tmp_path / "run")]
    with pytest.raises(_Built):
        run_cli(args)
    assert built == [[SubstrateContact]]
