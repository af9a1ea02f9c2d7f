"""``bristlecrawler --help`` on a terminal: the commands in the order a user meets them,
each summary whole at any width; ``sweep --help`` says which shipped studies take seconds
and which take minutes."""

import tomllib
from importlib import resources

import pytest

from terminal import cli, under_a_terminal


def _commands(text: str) -> dict[str, str]:
    """The Commands section: each command's summary, its wrapped lines joined."""
    section = text.split("Commands:", 1)[1]
    out: dict[str, str] = {}
    name = None
    for line in section.splitlines():
        if not line.strip():
            continue
        if line.startswith("  ") and not line.startswith("   "):
            name, _, summary = line.strip().partition(" ")
            out[name] = summary.strip()
        elif name is not None:
            out[name] += " " + line.strip()
    return out


@pytest.mark.parametrize("columns", [80, 160])
def test_commands_are_listed_as_a_user_meets_them_with_whole_summaries(columns):
    commands = _commands(under_a_terminal(cli("--help"), columns))
    names = list(commands)
    assert names[:4] == ["reproduce", "simulate", "predict", "sweep"], names
    assert names[-1] == "version"
    assert {"drag", "reduced", "analyze", "verify", "scenario"} <= set(names)
    for name, summary in commands.items():
        assert "..." not in summary, (name, summary)
        assert summary.endswith("."), (name, summary)


def test_sweep_help_says_which_shipped_studies_are_fe_and_which_reduced():
    folder = resources.files("bristlecrawler") / "studies"
    by_model: dict[str, list[str]] = {}
    for entry in sorted(folder.iterdir(), key=lambda p: p.name):
        if entry.name.endswith(".toml"):
            model = tomllib.loads(entry.read_text())["model"]
            by_model.setdefault(model, []).append(entry.name[:-5])
    text = " ".join(under_a_terminal(cli("sweep", "--help"), 100).split())
    assert f"{', '.join(by_model['reduced'])} (reduced model: seconds)" in text
    assert f"{', '.join(by_model['fe'])} (FE model: minutes per design)" in text
