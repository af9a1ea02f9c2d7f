"""Every command, driven with generated bad values: one ``error:`` line on stderr, exit
code 2, and no file or folder changed.

The bad values come from the schemas' own bounds (just beyond each bound, far beyond it,
NaN and infinities where finite numbers are required, words where numbers are) and from
corrupted data files, so a bound added to a schema is tested without a new test.
"""

import contextlib
import io
import math
import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import BaseModel

from bristlecrawler.cli.app import main
from bristlecrawler.experiment.recording import CHANNEL_LIMITS
from bristlecrawler.reduced.calibration import MAX_CYCLES, MAX_S, MAX_WORK
from bristlecrawler.scenario.drag import DragOptions
from bristlecrawler.scenario.experiment import AnalyzeOptions, SynthOptions
from bristlecrawler.scenario.reduced import ReducedConfig
from bristlecrawler.scenario.schema import MAX_LENGTH, Scenario
from bristlecrawler.scenario.strict import option_names
from bristlecrawler.scenario.substrate import SUBSTRATE_KINDS

JUNK = st.sampled_from(["abc", "", "1e", "0x1p3", "1,5", "--", "nan%", "\u00bd"])


def _bounds(field) -> dict:
    out = {"allow_inf_nan": True}
    for m in field.metadata:
        for key in ("gt", "ge", "lt", "le", "allow_inf_nan"):
            if hasattr(m, key):
                out[key] = getattr(m, key)
    return out


def bad_value(field):
    """Values outside ``field``'s bounds, as Python numbers (None when it has none)."""
    b = _bounds(field)
    options = []
    if field.annotation in (int, int | None):
        if "ge" in b:
            options.append(st.integers(max_value=b["ge"] - 1, min_value=b["ge"] - 10**20))
        if "le" in b:
            options.append(st.integers(min_value=b["le"] + 1, max_value=b["le"] + 10**20))
        if options:
            options.append(st.floats(0.1, 100).filter(lambda x: x != int(x)))
        return st.one_of(options) if options else None
    if field.annotation not in (float, float | None):
        return None
    floats = {"allow_nan": False, "allow_infinity": False}
    if "gt" in b:
        options.append(st.floats(max_value=b["gt"], **floats))
    if "ge" in b:
        options.append(st.floats(max_value=b["ge"], exclude_max=True, **floats))
    if "lt" in b:
        options.append(st.floats(min_value=b["lt"], **floats))
    if "le" in b:
        options.append(st.floats(min_value=b["le"], exclude_min=True, **floats))
    if not b["allow_inf_nan"]:
        options.append(st.sampled_from([math.nan, math.inf, -math.inf]))
    elif options:
        options.append(st.just(math.nan))
    return st.one_of(options) if options else None


def numeric_fields(model: type[BaseModel]):
    """(name, field, bad-value strategy) of every bounded number of ``model``."""
    out = []
    for name, field in model.model_fields.items():
        strategy = bad_value(field)
        if strategy is not None:
            out.append((name, field, strategy))
    return out


def cli_text(value) -> str:
    return value if isinstance(value, str) else repr(value)


def options_of(model, names, fixed=()):
    """Strategy: [--option, bad value] for one bounded field of ``model``."""
    fields = numeric_fields(model)
    return st.sampled_from(fields).flatmap(
        lambda f: st.one_of(f[2], JUNK).map(lambda v: [names[f[0]], cli_text(v)])
    )


def scenario_sets():
    """Strategy: --set section.key=value with a value outside that field's bounds."""
    pairs = []
    for section, field in Scenario.model_fields.items():
        ann = field.annotation
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            pairs += [(f"{section}.{n}", s) for n, _, s in numeric_fields(ann)]
    pairs += [(f"substrate.{n}", s) for n, _, s in numeric_fields(SUBSTRATE_KINDS["grooves"])]
    pairs += [(f"substrate.{n}", far(MAX_LENGTH)) for n in ("phase", "top")]
    pairs += [("gravity", s) for n, _, s in numeric_fields(Scenario) if n == "gravity"]
    words = st.sampled_from(['"abc"', "true", "[1, 2]", "{a = 1}"])
    return st.sampled_from(pairs).flatmap(
        lambda p: st.one_of(p[1].map(cli_text), words).map(lambda v: ["--set", f"{p[0]}={v}"])
    )


def far(limit: float, infinite: bool = True):
    """Numbers beyond +-limit (infinities too, if ``infinite``)."""
    big = st.floats(min_value=limit, exclude_min=True, allow_nan=False, allow_infinity=infinite)
    return st.one_of(big, big.map(lambda x: -x))


def calibrate_args():
    good = {"--s-max": "20", "--cycles": "5", "--advance": "82", "--work": "75"}
    bad = {
        "--s-max": st.one_of(st.floats(max_value=0), far(MAX_S), st.just(math.nan)),
        "--cycles": st.one_of(st.integers(max_value=0), st.integers(min_value=MAX_CYCLES + 1)),
        "--advance": st.one_of(st.floats(max_value=0), st.floats(min_value=100), st.just(math.inf)),
        "--work": st.one_of(st.floats(max_value=0), far(MAX_WORK), st.just(math.nan)),
    }

    def build(option, value):
        args = dict(good) | {option: cli_text(value)}
        return ["calibrate", *[x for kv in args.items() for x in kv]]

    return st.sampled_from(sorted(bad)).flatmap(
        lambda o: st.one_of(bad[o], JUNK).map(lambda v: build(o, v))
    )


RECORDING_COLUMNS = ("time_s", "left_mm", "right_mm", "current_A", "force_N")


def corrupt_recording(good: str):
    """A copy of a good recording with one cell beyond its channel's range."""
    rows = good.splitlines()
    units = dict(zip(RECORDING_COLUMNS, ("time", "left", "right", "current", "force"), strict=True))

    def build(row, col, value):
        out = list(rows)
        cells = out[row].split(",")
        cells[col] = cli_text(value)
        out[row] = ",".join(cells)
        return "\n".join(out) + "\n"

    columns = rows[0].split(",")

    def cell(name):
        col = columns.index(name)
        limit = CHANNEL_LIMITS[units[name]]
        # A row whose time is not finite is dropped as a logger's glitch: not an error.
        values = far(limit, infinite=col != 0)
        return st.tuples(st.integers(1, len(rows) - 1), st.just(col), values)

    present = [c for c in RECORDING_COLUMNS if c in columns]
    return st.sampled_from(present).flatmap(cell).map(lambda a: build(*a))


BAD_HISTORY = st.sampled_from(
    [
        "t,s\n0,0\n2,1\n1,2\n",
        "t,s\n0,0\n1,-2\n",
        "t,s\n0,0\n1,inf\n",
        "t,s\n0,0\n1e10,1\n",
        "t,s\n0,0\n10,150\n20,0\n",
        "t;s\n0;0\n1;1\n",
        "t,s\n",
        "\x00\x01",
    ]
)


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    """A folder with an old run, a data file and a good recording."""
    root = tmp_path_factory.mktemp("bad-input")
    old = root / "old"
    old.mkdir()
    (old / "meta.json").write_text('{"status": "complete"}\n')
    (old / "summary.json").write_text("{}\n")
    (root / "keep.csv").write_text("t,s\n0,0\n10,20\n20,0\n")
    rec = root / "rec.csv"
    assert _run(["synth-recording", str(rec), "--actuator", "sin2", "--cycles", "2"])[0] == 0
    # The good recording passes: only the corruption can make a test case fail.
    elsewhere = tmp_path_factory.mktemp("good-analysis")
    assert _run(["analyze", str(rec), "--no-figures", "--out", str(elsewhere / "a")]) == (0, "")
    return root


def _snapshot(root: Path) -> dict[str, bytes | int]:
    """Every file's bytes, and every folder's modification time (a file created and
    removed again changes it)."""
    return {
        str(p.relative_to(root)): p.read_bytes() if p.is_file() else p.stat().st_mtime_ns
        for p in sorted([root, *root.rglob("*")], key=str)
    }


def _run(args: list[str]) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            main(args)
            code = 0
        except SystemExit as exc:
            code = exc.code
    return code, err.getvalue()


VALID = {
    "reduced": ["reduced", "--no-figures"],
    "simulate": ["simulate", "paper", "--no-figures"],
    "analyze": ["analyze", "rec.csv", "--no-figures"],
    "drag": ["drag", "paper"],
    "reproduce": ["reproduce", "--quick"],
}

#: Names that must not become part of a folder's name.
UNSAFE_NAMES = st.one_of(
    st.sampled_from(["../../escape", "a/b", "..", ".hidden", "", "/abs", "a b", "-x", "\u00e9"]),
    st.text(min_size=1, max_size=80).filter(
        lambda t: not (t[:1].isascii() and t[:1].isalnum()) or not t.isascii() or len(t) > 64
    ),
)

#: A valid study; "{more}" takes extra top-level keys, "{axes}" the axes.
STUDY = 'name = "s"\nmodel = "reduced"\n{more}\n[axes]\n{axes}\n'


BAD_STUDY_KEYS = st.sampled_from(
    [
        ('samples = "3"', "s_max = { random = [1.0, 2.0] }"),
        ("samples = 3", 's_max = { random = [1.0, 2.0], log = "yes" }'),
        ("samples = 3", "s_max = { random = [1.0, 2.0], log = 1 }"),
        ("samples = 3", 's_max = { lhs = ["1", 2.0] }'),
        ("", "s_max = { linspace = [1.0, 2.0, 3.0] }"),
        ("", "s_max = { linspace = [true, 2.0, 3] }"),
        ("seed = true", "s_max = [10.0]"),
        ("seed = -1", "s_max = [10.0]"),
        ("chunk = 1.5", "s_max = [10.0]"),
        ("combine = 1", "s_max = [10.0]"),
        ('description = ["a"]', "s_max = [10.0]"),
        ("", "nosuch = [1.0]"),
        ("", "s_max = []"),
        ("", 's_max = [1.0, "a"]'),
        ("", "s_max = { linspace = [1.0, 100.0, 100000] }\nfp = { linspace = [0.1, 1.0, 1000] }"),
    ]
)


def sweep_args(data, work: Path) -> list[str]:
    """A sweep given a study file of the wrong types or sizes, an unsafe name, a bad
    scheduler address or a machine's worth of workers: each refused before a cluster."""
    kind = data.draw(st.sampled_from(["study", "name", "scheduler", "workers"]))
    more, axes = data.draw(BAD_STUDY_KEYS) if kind == "study" else ("", "s_max = [10.0, 20.0]")
    extra = ["--out", str(work / "new")]
    if kind == "name":
        more, extra = f"# unsafe\nname = {_toml(data.draw(UNSAFE_NAMES))}", []
    elif kind == "scheduler":
        extra.extend(["--scheduler", data.draw(st.text(max_size=30).filter(_not_an_address))])
    elif kind == "workers":
        many = st.one_of(st.integers(max_value=0), st.integers(10**3, 10**12))
        extra.extend(["--workers", str(data.draw(many))])
    text = STUDY.format(more=more, axes=axes)
    if kind == "name":
        text = text.replace('name = "s"\n', "")
    (work / "study.toml").write_text(text)
    return ["sweep", str(work / "study.toml"), *extra]


def _toml(text: str) -> str:
    import json

    return json.dumps(text)


def _not_an_address(text: str) -> bool:
    from bristlecrawler.studies.execute import _ADDRESS

    return _ADDRESS.fullmatch(text) is None


def drag_args(data, work: Path) -> list[str]:
    """drag with a bound broken, a name that would leave runs/, or work too large."""
    out = ["--out", str(work / "new")]
    kind = data.draw(st.integers(0, 3))
    if kind == 0:
        return ["drag", "paper", *data.draw(options_of(DragOptions, option_names(DragOptions)))]
    if kind == 1:
        return ["drag", "paper", "--set", f"name={_toml(data.draw(UNSAFE_NAMES))}"]
    if kind == 2:  # within every bound, beyond the machine: refused with the estimate
        legs = data.draw(st.integers(2_000, 10_000))
        return ["drag", "paper", "--legs", str(legs), "--distance", "1e4", *out]
    return ["drag", "paper", *data.draw(scenario_sets()), *out]


def _args(command: str, data, work: Path) -> list[str]:
    out = ["--out", str(work / "new")]
    if command in VALID and data.draw(st.integers(0, 5)) == 0:
        # Good values, an output path that cannot take the run.
        bad_out = data.draw(st.sampled_from(["old", "keep.csv", "keep.csv/sub", "."]))
        valid = [str(work / a) if a.endswith(".csv") else a for a in VALID[command]]
        return [*valid, "--out", str(work / bad_out)]
    if command == "reduced":
        names = option_names(ReducedConfig, samples_per_cycle="--samples-per-cycle")
        if data.draw(st.integers(0, 4)) == 0:
            (work / "h.csv").write_text(data.draw(BAD_HISTORY))
            return ["reduced", "--history", str(work / "h.csv"), *out]
        return ["reduced", *data.draw(options_of(ReducedConfig, names)), *out]
    if command == "simulate":
        if data.draw(st.integers(0, 4)) == 0:
            (work / "h.csv").write_text(data.draw(BAD_HISTORY))
            return ["simulate", "paper", "--history", str(work / "h.csv"), *out]
        if data.draw(st.integers(0, 4)) == 0:
            return ["simulate", "paper", "--set", f"name={_toml(data.draw(UNSAFE_NAMES))}"]
        return ["simulate", "paper", *data.draw(scenario_sets()), *out]
    if command == "calibrate":
        return data.draw(calibrate_args())
    if command == "drag":
        return drag_args(data, work)
    if command == "sweep":
        return sweep_args(data, work)
    if command == "reproduce":  # a recording with columns other than the ones read
        header = data.draw(st.sampled_from(["t,left,right", "time_s,left_mm", "a,b,c"]))
        (work / "cols.csv").write_text(f"{header}\n0,1,2\n1,2,3\n")
        return ["reproduce", "--quick", "--recording", str(work / "cols.csv"), *out]
    if command == "analyze":
        rec = str(work / "rec.csv")
        if data.draw(st.booleans()):
            (work / "bad.csv").write_text(
                data.draw(corrupt_recording((work / "rec.csv").read_text()))
            )
            rec = str(work / "bad.csv")
            return ["analyze", rec, "--no-figures", *out]
        if data.draw(st.booleans()):  # a column named that the recording does not have
            option = data.draw(st.sampled_from(["--time", "--left", "--right", "--force"]))
            column = data.draw(st.from_regex(r"[a-z_]{1,12}", fullmatch=True))
            return ["analyze", rec, "--no-figures", option, column + "_x", *out]
        names = option_names(AnalyzeOptions)
        return ["analyze", rec, "--no-figures", *data.draw(options_of(AnalyzeOptions, names)), *out]
    if command == "synth-recording":
        target = data.draw(st.sampled_from(["new.csv", "keep.csv", "old", "keep.csv/x.csv"]))
        if target != "new.csv":
            return ["synth-recording", str(work / target)]
        opts = options_of(SynthOptions, option_names(SynthOptions))
        return ["synth-recording", str(work / target), *data.draw(opts)]
    word = data.draw(
        st.from_regex(r"--[a-z]{2,10}", fullmatch=True).filter(lambda w: w != "--json")
    )
    return [command, word]


COMMANDS = ["reduced", "calibrate", "simulate", "analyze", "synth-recording", "verify", "version"]


@pytest.mark.parametrize("command", [*COMMANDS, "drag", "sweep", "reproduce"])
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_bad_values_give_one_line_exit_2_and_change_nothing(command, data, work):
    args = _args(command, data, work)
    before = _snapshot(work)
    with pytest.MonkeyPatch.context() as mp:
        # Run from the work folder: a default run folder (runs/...) would show there.
        mp.chdir(work)
        mp.setattr("bristlecrawler.jobs.simulate.solve", _never)
        mp.setattr("bristlecrawler.jobs.reduced.simulate", _never)
        mp.setattr("bristlecrawler.jobs.drag.solve_drag", _never)
        mp.setattr("bristlecrawler.studies.execute.connect", _never)
        mp.setattr("bristlecrawler.jobs.reproduce.run._run_parts", _never)
        try:
            code, err = _run(args)
        finally:  # a failing case leaves nothing that would change its replay
            shutil.rmtree(work / "new", ignore_errors=True)
            shutil.rmtree(work / "runs", ignore_errors=True)
            (work / "new.csv").unlink(missing_ok=True)
    assert code == 2, (args, err)
    assert err.startswith("error: ") and err.count("\n") == 1 and err.endswith("\n"), (args, err)
    assert _snapshot(work) == before, args


def _never(*args, **kwargs):
    raise AssertionError("bad input reached the solver")
