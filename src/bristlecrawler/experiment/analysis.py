"""One call from a recording to the gait analysis and the fitted reduced model."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from bristlecrawler.experiment.fit import ReducedFit, fit_reduced
from bristlecrawler.experiment.gait import Transition, per_cycle_advance, transitions
from bristlecrawler.experiment.options import AnalysisOptions
from bristlecrawler.experiment.preprocess import GaitSignals, prepare
from bristlecrawler.experiment.recording import Recording
from bristlecrawler.results import keys


@dataclass(frozen=True)
class Analysis:
    """Everything the analysis found in one recording."""

    signals: GaitSignals
    advance_per_cycle: np.ndarray
    transitions: list[Transition]
    fit: ReducedFit

    @property
    def net_advance(self) -> float:
        return float(np.sum(self.advance_per_cycle))

    def summary(self) -> dict[str, Any]:
        f = self.fit
        out: dict[str, Any] = {
            "cycles": self.signals.n_cycles,
            keys.NET_ADVANCE_MM: self.net_advance,
            keys.ADVANCE_PER_CYCLE_MM: self.advance_per_cycle.tolist(),
            "s_max_per_cycle_mm": f.s_max_mm.tolist(),
            "cycle_duration_s": np.diff(self.signals.t[self.signals.cycles[:, [0, 2]]], axis=1)
            .ravel()
            .tolist(),
            "fp_over_k_mm": f.fp_over_k_mm,
            "fp_over_k_ci_mm": list(f.fp_over_k_ci_mm),
            "fp_over_k_per_cycle_mm": [None if not np.isfinite(c) else c for c in f.per_cycle_mm],
            "fp_over_k_from_advance_mm": f.fp_over_k_from_advance_mm,
            "first_cycle_unloaded": f.first_cycle_unloaded,
            "fit_rms_residual_mm": f.rms_residual_mm,
            "transitions": [tr.as_dict() for tr in self.transitions],
            "notes": list(self.signals.notes) + list(f.notes),
        }
        if f.fp_N is not None:
            out |= {keys.FP_N: f.fp_N, keys.K_N_PER_MM: f.k_N_per_mm}
        return {
            k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in out.items()
        }


def analyze(
    rec: Recording,
    work_mJ: float | None = None,
    use_force: bool = True,
    max_gap_s: float = AnalysisOptions.max_gap,
    use_measured_shortening: bool = False,
) -> Analysis:
    """Clean, segment, detect stick/slip transitions and fit the reduced model."""
    sig = prepare(rec, max_gap_s=max_gap_s, use_measured_shortening=use_measured_shortening)
    force = None
    if use_force and rec.force is not None and work_mJ is None:
        first = int(np.flatnonzero(np.isclose(rec.t, sig.t[0]))[0])
        force = rec.force[first : first + sig.t.size]
        if not np.all(np.isfinite(force)):
            force = None
    fit = fit_reduced(sig, work_mJ=work_mJ, force_N=force)
    return Analysis(sig, per_cycle_advance(sig), transitions(sig), fit)
