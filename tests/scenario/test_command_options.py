"""The commands' option tables (``drag``, ``reduced``, ``analyze``, ``synth-recording``)
are generated from the settings their model objects declare: the same keys, defaults,
meanings and ranges, the same rules, and the same one-line refusal from Python and from
the table."""

import dataclasses

import pytest
import typer

from bristlecrawler.cli.app import app
from bristlecrawler.crawler import CrawlerSpec
from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.errors import InputError
from bristlecrawler.experiment.options import AnalysisOptions, SynthesisOptions
from bristlecrawler.reduced.run import ReducedRun
from bristlecrawler.scenario.drag import DragOptions
from bristlecrawler.scenario.experiment import AnalyzeOptions, SynthOptions
from bristlecrawler.scenario.reduced import ReducedConfig
from bristlecrawler.scenario.strict import option_names, parse_model
from bristlecrawler.settings import settings_of

#: command -> (its table, the declaring class, settings the command does not take)
TABLES = {
    "drag": (DragOptions, DragTest, {"bristle", "resolution"}),
    "reduced": (ReducedConfig, ReducedRun, set()),
    "analyze": (AnalyzeOptions, AnalysisOptions, set()),
    "synth-recording": (SynthOptions, SynthesisOptions, set()),
}


@pytest.mark.parametrize("command", TABLES)
def test_each_table_has_exactly_the_declared_settings(command):
    table, cls, left_out = TABLES[command]
    declared = {f.name: f for f in settings_of(cls) if f.name not in left_out}
    assert set(table.model_fields) == set(declared)
    for name, f in declared.items():
        field = table.model_fields[name]
        assert field.default == f.default, name
        assert field.description == f.metadata["doc"], name
        bounds = {
            k: getattr(m, k) for m in field.metadata for k in f.metadata["bounds"] if hasattr(m, k)
        }
        assert bounds == f.metadata["bounds"], name


@pytest.mark.parametrize("command", TABLES)
def test_the_command_line_defaults_are_the_declared_ones(command):
    table = TABLES[command][0]
    flags = option_names(table)
    params = typer.main.get_command(app).commands[command].params
    by_flag = {opt: p for p in params for opt in p.opts}
    for name, flag in flags.items():
        assert by_flag[flag].default == table.model_fields[name].default, flag


@pytest.mark.parametrize(
    ("cls", "table", "values"),
    [
        (ReducedRun, ReducedConfig, {"fn": 0.1}),
        (ReducedRun, ReducedConfig, {"s_max": 100.0}),
        (ReducedRun, ReducedConfig, {"fp": 1e5, "k": 1e-9}),
        (ReducedRun, ReducedConfig, {"cycles": 100_000, "samples_per_cycle": 10_000}),
        (ReducedRun, ReducedConfig, {"history": "h.csv", "actuator": "sma"}),
    ],
)
def test_a_rule_refuses_the_same_from_python_and_from_the_table(cls, table, values):
    with pytest.raises(InputError) as direct:
        cls(**values).check()
    with pytest.raises(InputError) as edge:
        parse_model(table, values)
    assert str(direct.value) == str(edge.value)
    assert "\n" not in str(direct.value)


@pytest.mark.parametrize(
    ("test", "message"),
    [
        (DragTest(speed=0.0), "drag speed must be >= 0.0001, got 0"),
        (DragTest(legs=1), "drag legs must be >= 2, got 1"),
        (DragTest(load=float("nan")), "drag load must be a number, got nan"),
        (
            DragTest(direction="sideways"),
            "drag direction must be one of along, against, cycle, got 'sideways'",
        ),
        (DragTest(legs=2.5), "drag legs must be a whole number, got 2.5"),
    ],
)
def test_a_drag_test_out_of_its_declared_range_is_one_line_naming_the_setting(test, message):
    with pytest.raises(InputError) as err:
        test.check(CrawlerSpec.paper())
    assert str(err.value) == message


def test_the_tables_give_the_objects_the_commands_use():
    assert DragOptions(speed=1.0, load=0.1).test() == DragTest(speed=1.0, load=0.1)
    config = parse_model(ReducedConfig, {"gait": "peristaltic", "bristles": 3})
    run = config.run()
    assert run == ReducedRun(gait="peristaltic", bristles=3)
    assert run.gait_of(run.analytic_stroke()).delays == (0.0, run.period / 4)
    assert config.fn_resolved == 3 * run.fp
    assert dataclasses.asdict(SynthesisOptions()) == SynthOptions().model_dump()
