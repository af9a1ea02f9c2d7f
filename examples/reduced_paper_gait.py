"""The paper's reduced model (Section 4): gait, energetics and calibration in a few lines.

Run ``python examples/reduced_paper_gait.py`` to print the numbers and write
``reduced_paper_gait.png``; the test-suite imports this file and checks its results.
"""

from __future__ import annotations

import bristlecrawler as bc

# Calibrate from the paper's measurements: 82 mm and 75 mJ over 5 cycles of s~ = 20 mm.
calibration = bc.calibrate(s_max=20.0, cycles=5, advance=82.0, work=75.0)

# A crawler with the calibrated bristles, driven by s(t) = s~ sin^2(pi t / T).
crawler = bc.ReducedCrawler.two_bristle(k=calibration.k_N_per_mm, fp=calibration.fp_N)
stroke = bc.Sin2Stroke(s_max=20.0, period=20.0)
result = bc.simulate(crawler, stroke, cycles=5, samples_per_cycle=2000)
advance_per_cycle, work_per_cycle = result.per_cycle()


def main() -> None:
    print(
        f"F_p/k = {calibration.fp_over_k_mm:.3f} mm, F_p = {calibration.fp_N:.3f} N, "
        f"k = {calibration.k_N_per_mm:.3f} N/mm"
    )
    print(f"net advance {result.net_advance:.2f} mm, work {result.work[-1]:.2f} mJ")
    print("advance per cycle (mm):", [round(float(a), 3) for a in advance_per_cycle])
    from bristlecrawler.viz import plot_delta_vs_s, save_figure

    save_figure(
        plot_delta_vs_s(result, title="paper crawler, calibrated"), "reduced_paper_gait.png"
    )


if __name__ == "__main__":
    main()
