"""Shared by the FE crawler studies (``convergence_crawler.py``, ``sensitivity_crawler.py``):
run a list of variants of one scenario and print one row per run, with the change of the
net advance (mm) and of the connector work (%) against the first row. Nothing is
asserted: these are studies, each row a full simulation."""

from __future__ import annotations

import time


def run_rows(base, variants, extra_columns: bool = False) -> list[dict]:
    """Run ``variants`` (label, list of ``section.key=value``) of scenario ``base``;
    returns the summaries (None for a failed run). ``strain`` is the largest bending strain
    of the bristles (above 0.5 a warning follows the row: outside the beam model).
    ``extra_columns`` adds the advance of each cycle, the mean |F_c| (N) and the first
    frequency (Hz)."""
    from bristlecrawler.crawler import run
    from bristlecrawler.errors import SolverError
    from bristlecrawler.jobs.simulate import summarize
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides

    head = (
        f"{'run':<20} {'advance mm':>11} {'d adv mm':>9} {'work mJ':>8} {'d work %':>9} "
        f"{'balance':>8} {'strain':>7} {'steps':>6} {'newton':>7} {'wall s':>7}"
    )
    if extra_columns:
        head += f" {'|F_c| N':>8} {'f1 Hz':>6}  per cycle mm"
    print(head)
    print("-" * len(head))
    ref = None
    out = []
    for label, sets in variants:
        sc = apply_overrides(base, sets)
        t0 = time.perf_counter()
        try:
            h = run(to_spec(sc))
        except SolverError as e:
            print(f"{label:<20} FAILED: {e}", flush=True)
            out.append(None)
            continue
        wall = time.perf_counter() - t0
        s = summarize(h, sc)
        out.append(s)
        adv, work = s["net_advance_mm"], s["work_mJ"]
        ref = ref or (adv, work)
        row = (
            f"{label:<20} {adv:11.4f} {adv - ref[0]:+9.4f} {work:8.3f} "
            f"{100 * (work - ref[1]) / abs(ref[1]):+9.2f} "
            f"{s['energy_balance_rel_error']:8.2%} {s['max_bristle_strain']:7.3f} {s['steps']:6d} "
            f"{s['newton_iterations']:7d} {wall:7.0f}"
        )
        if extra_columns:
            per = ", ".join(f"{x:.3f}" for x in s["advance_per_cycle_mm"])
            row += f" {s['mean_abs_connector_force_N']:8.3f} {s['first_frequency_hz']:6.1f}  {per}"
        print(row, flush=True)
        for w in s.get("warnings", []):
            print(f"{'':<20} warning: {w}", flush=True)
    return out
