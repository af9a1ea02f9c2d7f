"""``bristlecrawler reproduce``: one ``--quick`` run shared by the module, checked for the
table's rows, the report's figures and links, the files, the JSON; and bad input, which
must end with one line before any work starts."""

import base64
import dataclasses
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from bristlecrawler.errors import SolverError
from bristlecrawler.jobs import reproduce as rp
from bristlecrawler.jobs.reproduce import table

#: The rows the issue asks for: the paper's numbers, each beside ours.
REQUIRED_ROWS = (
    "net_advance_mm",
    "advance_per_cycle_mm",
    "work_mJ",
    "mean_connector_force_N",
    "fp_over_k_mm",
    "fp_N",
    "k_N_per_mm",
    "advance_alpha0_mm_per_cycle",
)
DOCS = Path(__file__).resolve().parents[2] / "docs"


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """One ``reproduce --quick --json`` in a fresh interpreter (its Dask workers need a
    real ``__main__``): (exit code, stdout, stderr, run folder)."""
    out = tmp_path_factory.mktemp("reproduce") / "run"
    cmd = [sys.executable, "-m", "bristlecrawler.cli.app", "reproduce", "--quick", "--json"]
    p = subprocess.run([*cmd, "--out", str(out)], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr, out


@pytest.fixture(scope="module")
def rows(quick):
    code, stdout, stderr, _ = quick
    assert code == 0, stderr[-3000:]
    return {r["key"]: r for r in json.loads(stdout)["rows"]}


@pytest.mark.slow
def test_every_part_ran_and_the_table_has_every_row(quick, rows):
    doc = json.loads(quick[1])
    assert doc["failed"] == []
    assert set(doc["parts"]) == {p.name for p in rp.PARTS}
    assert set(REQUIRED_ROWS) <= set(rows)
    for key in REQUIRED_ROWS:
        r = rows[key]
        assert r["paper"] is not None and r["quantity"] and r["source"], key
        assert r["ours"] is not None or r["ours_text"], key
        if r["ours"] is not None and r["paper"] is not None:
            assert r["difference"] == pytest.approx(r["ours"] - r["paper"])


@pytest.mark.slow
def test_the_papers_numbers_are_the_papers(rows):
    paper = {k: rows[k]["paper"] for k in REQUIRED_ROWS}
    assert paper == {
        "net_advance_mm": 82.0,
        "advance_per_cycle_mm": 16.4,
        "work_mJ": 75.0,
        "mean_connector_force_N": 0.45,
        "fp_over_k_mm": 0.95,
        "fp_N": 0.45,
        "k_N_per_mm": 0.48,
        "advance_alpha0_mm_per_cycle": 0.0,
    }


@pytest.mark.slow
def test_quick_numbers_are_physical(rows):
    """One cycle at alpha = pi/4 advances less than the stroke and more than half of it;
    alpha = 0 advances less than that on average; the quick run does not pretend to have
    five cycles; the synthetic recording gives back the F_p/k it was made with."""
    per_cycle = rows["advance_per_cycle_mm"]["ours"]
    assert 10.0 < per_cycle < 20.0
    assert abs(rows["advance_alpha0_mm_per_cycle"]["ours"]) < per_cycle
    for key in ("net_advance_mm", "work_mJ"):
        assert rows[key]["ours"] is None and "1 cycle" in rows[key]["ours_text"]
        assert rows[key]["agrees"] is None
    assert rows["fp_over_k_recording_mm"]["ours"] == pytest.approx(0.456 / 0.48, abs=0.02)
    assert 0.0 < rows["mean_connector_force_N"]["ours"] < 0.45


@pytest.mark.slow
def test_differences_give_a_reason_and_name_the_docs_section(quick, rows):
    """The report travels without the docs: a difference names the section that explains
    it (and table.json gives its page in docs/), no relative link."""
    page = (quick[3] / "report.html").read_text(encoding="utf-8")
    for r in rows.values():
        assert r["verdict"] in ("agrees", "differs", "inconclusive", "n/a"), r["key"]
        if r["verdict"] in ("differs", "inconclusive"):
            assert r["reason"] and r["docs"] and r["link"], r["key"]
            assert (DOCS / r["link"].partition("#")[0]).is_file(), r["link"]
    assert "../docs/" not in page and "docs/findings.md" not in page
    assert "<th>verdict</th>" in page and "This part took" in page


@pytest.mark.slow
def test_the_run_folder_holds_the_report_and_its_provenance(quick):
    out = quick[3]
    for name in ("report.html", "report.md", "table.json", "config.json", "meta.json"):
        assert (out / name).stat().st_size > 0, name
    meta = json.loads((out / "meta.json").read_text())
    assert meta["status"] == "complete" and meta["git_revision"] and meta["package_version"]
    config = json.loads((out / "config.json").read_text())
    assert config["settings"]["quick"] is True
    assert json.loads((out / "table.json").read_text())["rows"] == json.loads(quick[1])["rows"]


def _decoded(uri: str) -> bytes:
    head, _, data = uri.partition(",")
    assert head in ("data:image/png;base64", "data:image/gif;base64"), head
    raw = base64.b64decode(data, validate=True)
    assert raw[:8] == b"\x89PNG\r\n\x1a\n" or raw[:6] in (b"GIF87a", b"GIF89a")
    return raw


@pytest.mark.slow
def test_every_figure_and_link_of_the_html_resolves(quick, rows):
    out = quick[3]
    page = (out / "report.html").read_text(encoding="utf-8")
    images = re.findall(r'<img src="([^"]+)"', page)
    assert len(images) >= 8  # experiment, FE x 4, alpha = 0, reduced x 2, drag, study
    for src in images:
        assert src.startswith("data:"), "the HTML must not depend on files beside it"
        _decoded(src)
    assert b"GIF8" in b"".join(_decoded(s)[:4] for s in images)  # the animation
    for href in re.findall(r'<a href="([^"]+)"', page):
        if href.startswith(("http://", "https://")):
            continue
        assert (out / href.partition("#")[0]).exists(), href
    for key in REQUIRED_ROWS:
        assert f'id="row-{key}"' in page
    assert "This part failed" not in page


@pytest.mark.slow
def test_every_figure_of_the_markdown_exists(quick):
    out = quick[3]
    text = (out / "report.md").read_text(encoding="utf-8")
    links = re.findall(r"\]\(([^)\s]+)\)", text)
    assert any(link.endswith(".gif") for link in links)
    for link in links:
        if not link.startswith(("http://", "https://")):
            assert (out / link.partition("#")[0]).exists(), link


def test_the_quoted_reasons_are_in_the_docs():
    for quote, page in table.QUOTED.items():
        text = " ".join((DOCS / page).read_text(encoding="utf-8").split())
        assert " ".join(quote.split()) in text, (page, quote[:40])


@pytest.mark.slow
def test_an_out_folder_holding_a_run_is_refused_untouched(quick, run_cli):
    out = quick[3]
    before = sorted((p.name, p.stat().st_mtime_ns) for p in out.iterdir())
    code, stdout, err = run_cli(["reproduce", "--quick", "--out", str(out)])
    assert code == 2 and stdout == ""
    assert err.startswith("error: ") and err.count("\n") == 1 and "already holds a run" in err
    assert sorted((p.name, p.stat().st_mtime_ns) for p in out.iterdir()) == before


@pytest.mark.parametrize(
    ("content", "words"),
    [(None, "no such file"), ("a,b\n1,2\n", "left-end channel"), ("", "")],
    ids=["missing", "wrong-columns", "empty"],
)
def test_a_bad_recording_is_refused_before_any_work(tmp_path, run_cli, content, words):
    rec = tmp_path / "trial.csv"
    if content is not None:
        rec.write_text(content)
    out = tmp_path / "run"
    code, stdout, err = run_cli(
        ["reproduce", "--quick", "--recording", str(rec), "--out", str(out)]
    )
    assert code == 2 and stdout == ""
    assert err.startswith("error: --recording") and err.count("\n") == 1 and words in err
    assert not out.exists() and list(tmp_path.iterdir()) == ([rec] if content is not None else [])


def _boom(ctx):
    raise SolverError("Newton did not converge at t = 1.5 s")


def test_a_failed_part_is_reported_and_the_rest_written(tmp_path, run_cli, monkeypatch):
    """A solver failure costs its own section: the report is complete otherwise and the
    exit code is 1."""
    real = rp.run_reproduce
    parts = (rp.Part("fe-paper", "FE model", _boom), *(p for p in rp.PARTS if p.name == "reduced"))
    monkeypatch.setattr(
        rp, "run_reproduce", lambda opts: real(dataclasses.replace(opts, parts=parts))
    )
    out = tmp_path / "run"
    code, stdout, err = run_cli(["reproduce", "--quick", "--json", "--out", str(out)])
    assert code == 1
    assert "error: part fe-paper failed: solver failed: Newton did not converge" in err
    doc = json.loads(stdout)
    assert doc["failed"] == ["fe-paper"]
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "This part failed" in page and "Newton did not converge" in page
    assert (out / "reduced-delta-vs-s.png").is_file()
    rows = {r["key"]: r for r in doc["rows"]}
    assert rows["net_advance_mm"]["ours"] is None
    assert rows["net_advance_mm"]["ours_text"] == "fe-paper failed"
    # The reduced model's calibration on the FE run says why it is missing.
    assert "did not finish" in (out / "report.md").read_text(encoding="utf-8")


def test_a_given_recording_is_analysed_instead_of_the_synthetic_one(tmp_path):
    from bristlecrawler.experiment import SensorModel, synthetic_recording, write_csv
    from bristlecrawler.jobs.reproduce.experiment_part import load_recording
    from bristlecrawler.reduced import ReducedCrawler

    path = tmp_path / "trial.csv"
    crawler = ReducedCrawler.two_bristle(fp=0.3, k=0.5)  # F_p/k = 0.6 mm, not the paper's
    write_csv(synthetic_recording(crawler, cycles=3, sensor=SensorModel()), path)
    _, analysis, source = load_recording(path)
    assert source == path and analysis.signals.n_cycles == 3
    assert analysis.fit.fp_over_k_mm == pytest.approx(0.6, abs=0.02)


def test_open_hands_the_written_report_to_the_browser(tmp_path, run_cli, monkeypatch):
    """``--open`` opens the report the run wrote, as a file URI, once it is written."""
    import webbrowser

    real = rp.run_reproduce
    parts = tuple(p for p in rp.PARTS if p.name == "reduced")
    monkeypatch.setattr(
        rp, "run_reproduce", lambda opts: real(dataclasses.replace(opts, parts=parts))
    )
    opened = []

    def browser(uri):
        opened.append((uri, Path(uri.removeprefix("file://")).is_file()))
        return True

    monkeypatch.setattr(webbrowser, "open", browser)
    out = tmp_path / "run"
    code, _, err = run_cli(["reproduce", "--quick", "--json", "--open", "--out", str(out)])
    assert code == 0, err
    assert opened == [((out / "report.html").resolve().as_uri(), True)]
