"""Experiments (paper Section 2, Fig. 3): a transducer recording analysed.

Without ``--recording`` the recording is the toolkit's synthetic one: the paper's SMA
stroke (s~ = 20 mm, about 20 s a cycle, five cycles), the reduced model with the paper's
F_p = 0.456 N and k = 0.48 N/mm, sensor noise, offsets, drift and dropouts, sampled at
100 samples/s like the prototype's cRIO.
"""

from __future__ import annotations

from pathlib import Path

from bristlecrawler.jobs.reproduce.parts import Context, Figure, Part, PartResult
from bristlecrawler.results import keys

#: The synthetic trial's reduced model: the paper's calibration (Section 4).
SYNTH_FP_N = 0.456
SYNTH_K_N_PER_MM = 0.48


def load_recording(path: Path | None):
    """The recording and its analysis, read and checked before any folder is claimed:
    a file that is missing, unreadable or holds no gait is an InputError (exit code 2)."""
    from bristlecrawler.errors import InputError
    from bristlecrawler.experiment import ChannelMap, analyze, read_recording

    if path is None:
        from bristlecrawler.experiment import SensorModel, synthetic_recording
        from bristlecrawler.reduced import ReducedCrawler

        crawler = ReducedCrawler.two_bristle(fp=SYNTH_FP_N, k=SYNTH_K_N_PER_MM)
        rec = synthetic_recording(crawler, actuator="sma", cycles=5, sensor=SensorModel())
        return rec, analyze(rec), None
    if not path.is_file():
        raise InputError(f"--recording {path}: no such file")
    try:
        rec = read_recording(path, ChannelMap())
        analysis = analyze(rec)
    except InputError as exc:
        raise InputError(f"--recording {path}: {exc}") from None
    except (ValueError, KeyError, IndexError, UnicodeDecodeError) as exc:
        # The readers' own checks give InputError; anything else is a file they could not
        # make sense of.
        raise InputError(f"--recording {path}: not a readable recording ({exc})") from None
    return rec, analysis, path


def run_experiment(ctx: Context) -> PartResult:
    from bristlecrawler.experiment import write_csv
    from bristlecrawler.viz.experiment import plot_analysis
    from bristlecrawler.viz.reduced import save_figure

    rec, analysis, path = ctx.inputs["recording"]
    s = analysis.summary()
    figures = [
        Figure(
            "experiment-delta-vs-s.png",
            "Delta(s) of the recording (grey), the "
            "fitted reduced model's loops (stick dashed blue, slip red) and the "
            "detected stick/slip transitions (dots): paper Fig. 3.",
        )
    ]
    save_figure(plot_analysis(analysis), ctx.folder / figures[0].path)
    if path is None:
        write_csv(rec, ctx.folder / "recording.csv")
        source = (
            "the toolkit's synthetic recording (`recording.csv`): the paper's SMA stroke to "
            f"s~ = 20 mm, five cycles, the reduced model with F_p = {SYNTH_FP_N} N and "
            f"k = {SYNTH_K_N_PER_MM} N/mm, sensor noise 0.01 mm, offsets, drift and "
            "dropouts, 100 samples/s"
        )
    else:
        source = f"the recording `{path}`"
    ci = s["fp_over_k_ci_mm"]
    per_cycle = ", ".join(f"{a:.2f}" for a in s[keys.ADVANCE_PER_CYCLE_MM])
    lines = [
        f"Analysed: {source}.",
        "",
        f"* {s['cycles']} cycles, net advance **{s[keys.NET_ADVANCE_MM]:.2f} mm** "
        f"(per cycle: {per_cycle} mm; paper: about 82 mm over five cycles, ± 1 mm).",
        f"* F_p/k = **{_num(s['fp_over_k_mm'], 3)} mm**, 95 % interval "
        f"[{_num(ci[0], 3)}, {_num(ci[1], 3)}] mm over the cycles; from the net advance "
        f"alone {_num(s['fp_over_k_from_advance_mm'], 3)} mm (paper: 0.95 mm).",
        f"* {len(s['transitions'])} stick/slip transitions detected.",
    ]
    if keys.FP_N in s:
        lines.append(
            f"* From the force channel: F_p = {_num(s[keys.FP_N], 3)} N, "
            f"k = {_num(s[keys.K_N_PER_MM], 3)} N/mm."
        )
    lines += [f"* note: {n}" for n in s["notes"]]
    values = {
        "source": "synthetic" if path is None else str(path),
        "cycles": s["cycles"],
        keys.NET_ADVANCE_MM: s[keys.NET_ADVANCE_MM],
        keys.ADVANCE_PER_CYCLE_MM: s[keys.ADVANCE_PER_CYCLE_MM],
        "fp_over_k_mm": s["fp_over_k_mm"],
        "fp_over_k_ci_mm": ci,
    }
    return PartResult("experiment", values=values, figures=tuple(figures), lines=tuple(lines))


def _num(x, digits: int) -> str:
    return "n/a" if x is None else f"{x:.{digits}f}"


EXPERIMENT = Part(
    "experiment",
    "Experiments: a transducer recording analysed (Section 2, Fig. 3)",
    run_experiment,
    cost=1.0,
)
