"""Every Python block of the README and the docs runs as written; every shell command
names a command and options that exist."""

import shlex

import pytest

from .pages import ROOT, blocks, shell_commands

PYTHON = blocks("python")
SHELL = blocks("bash")


@pytest.mark.slow
@pytest.mark.parametrize("page, index, code", PYTHON, ids=[f"{p}#{i}" for p, i, _ in PYTHON])
def test_python_block_runs(page, index, code, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # files a block writes land here
    exec(compile(code, f"{page} block {index}", "exec"), {"__name__": "__main__"})
    assert capsys.readouterr().out.strip(), "a documented example should print its result"


def _click_command():
    import typer.main

    from bristlecrawler.cli.app import app

    return typer.main.get_command(app)


def parse_cli(args: list[str]) -> None:
    """Parse ``bristlecrawler ARGS`` as the CLI would, without running the command."""
    group = _click_command()
    ctx = group.make_context("bristlecrawler", list(args), resilient_parsing=False)
    cmd, rest = group, _remaining(ctx)
    while rest and hasattr(cmd, "resolve_command"):
        _, sub, rest = cmd.resolve_command(ctx, rest)
        cmd = sub
        ctx = cmd.make_context(cmd.name, rest, parent=ctx)
        rest = _remaining(ctx)
    assert not rest, f"unparsed arguments {rest}"


def _remaining(ctx) -> list[str]:
    # a group's context keeps the sub-command's name apart (click and Typer's copy of it)
    protected = getattr(ctx, "_protected_args", None)
    if protected is None:
        protected = getattr(ctx, "protected_args", [])
    return [*protected, *ctx.args]


def test_the_parser_refuses_what_the_cli_refuses():
    with pytest.raises(Exception, match="--no-such"):
        parse_cli(["simulate", "paper", "--no-such-option"])
    with pytest.raises(Exception, match=r"(?i)no such command"):
        parse_cli(["simulat", "paper"])
    parse_cli(["simulate", "paper", "--cycles", "1", "--set", "bristle.elements=4"])


COMMANDS = [(page, cmd) for page, _, code in SHELL for cmd in shell_commands(code)]


@pytest.mark.parametrize("page, command", COMMANDS, ids=[f"{p}: {c}" for p, c in COMMANDS])
def test_shell_command_exists(page, command, tmp_path, monkeypatch):
    words = shlex.split(command)
    if words[0] == "bristlecrawler":
        monkeypatch.chdir(tmp_path)
        for w in words[1:]:  # files the command reads: placeholders will do for parsing
            if w.endswith((".csv", ".toml", ".tdms")) and "/" not in w:
                (tmp_path / w).write_text("")
        parse_cli(words[1:])
    elif words[0] == "python" and words[1].endswith(".py"):
        assert (ROOT / words[1]).is_file(), words[1]
    elif words[:2] == ["python", "-m"]:
        assert words[2] in ("pytest", "mkdocs"), command
    elif words[0] == "mkdocs":
        assert words[1] in ("serve", "build")
    else:
        assert words[0] in ("python3", "pip", "cat", ".", "source"), command


def test_every_cli_option_is_in_the_readme_and_the_cli_reference():
    """The CLI tables list every command and option that exists."""
    readme = (ROOT / "README.md").read_text()
    reference = (ROOT / "docs" / "reference" / "cli.md").read_text()

    def walk(cmd, path):
        if hasattr(cmd, "commands"):
            for name, sub in cmd.commands.items():
                yield from walk(sub, [*path, name])
        else:
            yield path, [o for p in cmd.params for o in p.opts if o.startswith("--")]

    for path, options in walk(_click_command(), []):
        name = "bristlecrawler " + " ".join(path)
        assert name in readme, name
        assert " ".join(path) in reference, name
        for opt in options:
            assert f"`{opt}" in reference or f"{opt}/" in reference, (name, opt)
            assert opt in readme, (name, opt)


def test_no_option_in_the_readme_table_is_made_up():
    import re

    readme = (ROOT / "README.md").read_text()
    table = [line for line in readme.splitlines() if line.startswith("| `bristlecrawler ")]
    known = set()
    for cmd in _walk_leaves(_click_command()):
        known |= {o for p in cmd.params for o in [*p.opts, *p.secondary_opts]}
    for line in table:
        for opt in re.findall(r"(--[a-z][a-z-]*)", line):
            assert opt in known, opt


def _walk_leaves(cmd):
    if hasattr(cmd, "commands"):
        for sub in cmd.commands.values():
            yield from _walk_leaves(sub)
    else:
        yield cmd


def test_docs_do_not_tell_development_history():
    import re

    pattern = re.compile(
        r"\bsessions?\b|\bissue #?\d|\b20\d\d-\d\d-\d\d\b|investigation log|"
        r"\b(first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|"
        r"twelfth|thirteenth|fourteenth) (session|period)\b",
        re.I,
    )
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        for n, line in enumerate(page.read_text().splitlines(), 1):
            assert not pattern.search(line), f"{page.name}:{n}: {line}"


def test_readme_links_point_to_files_that_exist():
    import re

    readme = (ROOT / "README.md").read_text()
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", readme)
    local = [link for link in links if not link.startswith(("http://", "https://"))]
    assert local
    for link in local:
        assert (ROOT / link).exists(), link
