"""Run the CLI in-process and capture its exit code and output."""

import pytest

from bristlecrawler.cli.app import main


@pytest.fixture
def run_cli(capsys):
    def run(args):
        try:
            main(args)
            code = 0
        except SystemExit as exc:
            code = exc.code
        out = capsys.readouterr()
        return code, out.out, out.err

    return run
