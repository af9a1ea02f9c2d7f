"""``bristlecrawler analyze`` and ``bristlecrawler synth-recording``: the experiment side."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from bristlecrawler.cli.options import OutFolder, ReplaceRun
from bristlecrawler.errors import printable
from bristlecrawler.results import keys


def analyze_cmd(
    recording: Annotated[Path, typer.Argument(help="CSV or TDMS file of the two transducers")],
    work: Annotated[
        float | None, typer.Option("--work", help="actuator work over the analysed cycles, mJ")
    ] = None,
    time_col: Annotated[
        str | None,
        typer.Option(
            "--time",
            help="time column/channel (s), which must exist [default: time_s if present, "
            "else uniform samples at --rate]",
        ),
    ] = None,
    left_col: Annotated[
        str, typer.Option("--left", help="left (rear) end displacement column, mm")
    ] = "left_mm",
    right_col: Annotated[
        str, typer.Option("--right", help="right (front) end displacement column, mm")
    ] = "right_mm",
    force_col: Annotated[
        str | None,
        typer.Option(
            "--force",
            help="connector force column, N, which must exist [default: force_N if present]",
        ),
    ] = None,
    flip_left: Annotated[bool, typer.Option("--flip-left", help="negate the left channel")] = False,
    flip_right: Annotated[
        bool, typer.Option("--flip-right", help="negate the right channel")
    ] = False,
    rate: Annotated[
        float, typer.Option("--rate", help="sample rate without a time column, samples/s")
    ] = 100.0,
    group: Annotated[
        str | None, typer.Option("--group", help="TDMS group [default: first]")
    ] = None,
    max_gap: Annotated[float, typer.Option("--max-gap", help="longest dropout bridged, s")] = 0.5,
    out: OutFolder = None,
    replace: ReplaceRun = False,
    as_json: Annotated[
        bool, typer.Option("--json", help="print the summary as JSON on stdout")
    ] = False,
    no_figures: Annotated[bool, typer.Option("--no-figures", help="skip the figure")] = False,
) -> None:
    """Analyse a recording of the prototype: advance per cycle, stick and slip, F_p/k.

    Finds the cycles, the advance of each, the stick/slip transitions and the fitted F_p/k
    with a bootstrap interval (and F_p, k with --work or a force channel)."""
    from bristlecrawler.experiment import ChannelMap, analyze, read_recording
    from bristlecrawler.io.jsonio import dumps_strict, finite_or_none
    from bristlecrawler.io.runs import check_out_dir, claim_run_dir
    from bristlecrawler.scenario.experiment import AnalyzeOptions
    from bristlecrawler.scenario.strict import option_names, parse_model

    opts = parse_model(
        AnalyzeOptions,
        {"work": work, "rate": rate, "max_gap": max_gap},
        option_names(AnalyzeOptions),
    )
    check_out_dir(out, replace)
    named = tuple(r for r, v in (("time", time_col), ("force", force_col)) if v is not None)
    cmap = ChannelMap(
        time=time_col or "time_s",
        left=left_col,
        right=right_col,
        force=force_col or "force_N",
        named=named,
        left_sign=-1.0 if flip_left else 1.0,
        right_sign=-1.0 if flip_right else 1.0,
        rate_hz=opts.rate,
        group=group,
    )
    rec = read_recording(recording, cmap)
    result = analyze(rec, work_mJ=opts.work, max_gap_s=opts.max_gap)
    summary = finite_or_none(result.summary() | {"recording": str(recording)})
    command = "bristlecrawler " + shlex.join(sys.argv[1:])
    figure = None
    if not no_figures:
        from bristlecrawler.viz.experiment import plot_analysis

        figure = plot_analysis(result)  # drawn before the folder is claimed: nothing to undo
    with claim_run_dir(out, "analyze", replace=replace, command=command) as run:
        config = {"recording": str(recording), "channels": cmap.__dict__} | opts.model_dump()
        run.write_metadata(config, command)
        run.write_json("analysis.json", summary)
        run.results_written("analysis.json")
        if figure is not None:
            from bristlecrawler.viz.reduced import save_figure

            save_figure(figure, run.path / "analysis.png")
    for note in run.notes:
        typer.echo(f"warning: {printable(note)}", err=True)
    summary["output_dir"] = str(run.target)
    if as_json:
        typer.echo(dumps_strict(summary))
        return
    _print_analysis(summary)


def _print_analysis(summary: dict) -> None:
    ci = summary["fp_over_k_ci_mm"]
    typer.echo(f"{summary['cycles']} cycles, net advance {summary[keys.NET_ADVANCE_MM]:.2f} mm")
    typer.echo(
        "advance per cycle (mm): "
        + ", ".join(f"{a:.2f}" for a in summary[keys.ADVANCE_PER_CYCLE_MM])
    )
    ci_txt = "n/a" if ci[0] is None else f"[{ci[0]:.3f}, {ci[1]:.3f}]"
    c = summary["fp_over_k_mm"]
    from_adv = summary["fp_over_k_from_advance_mm"]
    typer.echo(
        f"F_p/k = {'n/a' if c is None else f'{c:.3f}'} mm, 95% CI {ci_txt} "
        f"(from net advance: {'n/a' if from_adv is None else f'{from_adv:.3f}'} mm)"
    )
    if keys.FP_N in summary:
        typer.echo(f"F_p = {summary[keys.FP_N]:.3f} N, k = {summary[keys.K_N_PER_MM]:.3f} N/mm")
    for note in summary["notes"]:
        typer.echo(f"note: {printable(note)}")
    typer.echo(f"results in {printable(summary['output_dir'])}")


def synth_cmd(
    path: Annotated[Path, typer.Argument(help="output file, .csv or .tdms")],
    actuator: Annotated[str, typer.Option("--actuator", help="sma | sin2")] = "sma",
    cycles: Annotated[int, typer.Option("--cycles", help="number of cycles")] = 5,
    fp: Annotated[float, typer.Option("--fp", help="F_p, N")] = 0.456,
    k: Annotated[float, typer.Option("--k", help="bristle stiffness, N/mm")] = 0.48,
    noise: Annotated[float, typer.Option("--noise", help="sensor noise, mm (std)")] = 0.01,
    skip: Annotated[float, typer.Option("--skip", help="seconds cut from the start")] = 0.0,
    seed: Annotated[int, typer.Option("--seed", help="random seed (>= 0)")] = 0,
    replace: Annotated[
        bool, typer.Option("--replace", help="overwrite the file if it exists")
    ] = False,
) -> None:
    """Write a synthetic recording made by the reduced model with sensor artefacts."""
    from bristlecrawler.errors import InputError
    from bristlecrawler.experiment import SynthesisOptions, write_csv, write_tdms
    from bristlecrawler.io.runs import check_new_file
    from bristlecrawler.scenario.experiment import SynthOptions
    from bristlecrawler.scenario.strict import option_names, parse_model

    ext = path.suffix.lower()
    if ext not in (".csv", ".tdms"):
        raise InputError(f"output must end in .csv or .tdms, got '{path.name}'")
    opts = parse_model(
        SynthOptions,
        {
            "actuator": actuator,
            "cycles": cycles,
            "fp": fp,
            "k": k,
            "noise": noise,
            "skip": skip,
            "seed": seed,
        },
        option_names(SynthOptions),
    )
    check_new_file(path, replace)
    rec = SynthesisOptions(**opts.model_dump()).recording()
    (write_tdms if ext == ".tdms" else write_csv)(rec, path)
    typer.echo(f"wrote {printable(str(path))} ({rec.t.size} samples, {rec.duration:.1f} s)")


def register(app: typer.Typer) -> None:
    app.command("analyze")(analyze_cmd)
    app.command("synth-recording")(synth_cmd)
