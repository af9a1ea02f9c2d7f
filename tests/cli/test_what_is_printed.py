"""What the tool prints of what it reads: an error names the problem without quoting a
file's content (the file may be someone's secret, named by a scenario from someone else),
and nothing a user or a file supplies reaches the terminal as a control sequence."""

from pathlib import Path

import pytest

from bristlecrawler.errors import printable

SECRET = "hunter2-token-0xDEADBEEF"


@pytest.mark.parametrize(
    "text",
    [f"{SECRET},x\n0,1\n", f"t,s\n0,0\n{SECRET},1\n", f"t,s\n0,0\n1,{SECRET}\n"],
    ids=["header", "time cell", "shortening cell"],
)
def test_a_history_error_names_the_problem_without_quoting_the_file(tmp_path, run_cli, text):
    secret = tmp_path / "secret.csv"
    secret.write_text(text)
    secret.chmod(0o600)
    (tmp_path / "link.csv").symlink_to(secret)
    out = tmp_path / "run"
    code, _, err = run_cli(["reduced", "--history", str(tmp_path / "link.csv"), "--out", str(out)])
    assert (code, err.count("\n")) == (2, 1), err
    assert "history file" in err and ("column" in err or "not both numbers" in err), err
    assert SECRET not in err and "hunter2" not in err
    assert not out.exists()


def test_a_scenario_s_history_file_is_not_quoted_either(tmp_path, run_cli):
    (tmp_path / "secret.csv").write_text(f"{SECRET}\n")
    (tmp_path / "s.toml").write_text(
        f'base = "paper"\n[actuation]\nkind = "history"\nhistory = "{tmp_path / "secret.csv"}"\n'
    )
    code, _, err = run_cli(["simulate", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o")])
    assert (code, err.count("\n")) == (2, 1) and "lacks column(s) t, s" in err, err
    assert SECRET not in err


def test_a_recording_s_column_names_and_cells_are_not_quoted(tmp_path, run_cli):
    rows = f"time_s,{SECRET},right_mm\n" + "".join(f"{i},{i},{i}\n" for i in range(20))
    (tmp_path / "r.csv").write_text(rows)
    code, _, err = run_cli(["analyze", str(tmp_path / "r.csv"), "--out", str(tmp_path / "o")])
    assert (code, err.count("\n")) == (2, 1) and "no left-end channel 'left_mm'" in err, err
    assert SECRET not in err


def test_printable_escapes_every_control_character_and_keeps_the_rest():
    assert printable("bristle.\x1b]0;owned\x07 \u202e\r\t Ø mm") == (
        "bristle.\\x1b]0;owned\\x07 \\u202e\\r\\t Ø mm"
    )
    assert printable("a\nb\tc", keep="\n\t") == "a\nb\tc"


def test_an_escape_sequence_in_a_scenario_key_reaches_the_terminal_escaped(tmp_path, run_cli):
    (tmp_path / "s.toml").write_text('base = "paper"\n[bristle]\n"\\u001b]0;owned\\u0007" = 1\n')
    code, out, err = run_cli(["simulate", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o")])
    assert (code, err.count("\n")) == (2, 1), err
    assert "\x1b" not in err + out and "\x07" not in err + out
    assert "\\x1b]0;owned\\x07" in err


def test_an_escape_sequence_in_an_output_path_is_printed_escaped(tmp_path, run_cli):
    out = tmp_path / "run-\x1b[2J-\x07"
    code, stdout, err = run_cli(["reduced", "--cycles", "1", "--out", str(out)])
    assert code == 0, err
    assert (out / "summary.json").is_file()
    assert "\x1b" not in stdout + err and "\x07" not in stdout + err
    assert "run-\\x1b[2J-\\x07" in stdout.replace("\n", "")  # rich wraps long lines


@pytest.mark.parametrize(
    "name",
    [".victim.partial-ab12cd_9", ".victim.lock", ".victim.old-0a1b2c3d", ".study.zarr.123"],
)
def test_a_name_the_tool_keeps_for_its_bookkeeping_is_refused_as_out(tmp_path, run_cli, name):
    code, _, err = run_cli(["reduced", "--cycles", "1", "--out", str(tmp_path / name)])
    assert (code, err.count("\n")) == (2, 1) and "a name the tool keeps" in err, err
    assert list(tmp_path.iterdir()) == []


def test_a_run_into_a_live_run_s_partial_folder_is_refused_and_the_live_run_completes(
    tmp_path, run_cli
):
    from bristlecrawler.io.runs import claim_run_dir, run_status

    with claim_run_dir(tmp_path / "victim", "reduced") as live:
        partial = Path(live.path)  # empty until the live run writes its first file
        code, _, err = run_cli(["reduced", "--cycles", "1", "--out", str(partial)])
        assert (code, err.count("\n")) == (2, 1) and "a name the tool keeps" in err, err
        # Through a link too, and with --replace once the live run has written files.
        live.write_json("summary.json", {"mine": True})
        (tmp_path / "innocent").symlink_to(partial)
        args = ["reduced", "--cycles", "1", "--replace", "--out", str(tmp_path / "innocent")]
        code, _, err = run_cli(args)
        assert code == 2 and "a name the tool keeps" in err, err
        assert sorted(p.name for p in partial.iterdir()) == ["summary.json"]
    assert run_status(tmp_path / "victim") == "complete"
    assert sorted(p.name for p in (tmp_path / "victim").iterdir()) == ["meta.json", "summary.json"]


def test_the_line_a_long_command_starts_with_is_escaped(capsys):
    from bristlecrawler.viz.progress import announce

    announce("sweep", "20 designs into runs/\x1b]0;owned\x07")
    err = capsys.readouterr().err
    assert err == "sweep: 20 designs into runs/\\x1b]0;owned\\x07\n"
