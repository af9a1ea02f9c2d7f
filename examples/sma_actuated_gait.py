"""The closed-loop SMA actuator drives the reduced model; the gait matches the sin^2 stroke.

Paper Section 2: 3.5 A until s reaches 20 mm, then off until the crawler is back at its
length, about 20 s per cycle. The reduced model is quasi-static (rate-independent), so the
advance per cycle depends only on the stroke's turning points, not on how it is played.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np

import bristlecrawler as bc
from bristlecrawler.experiment import SMAActuator, run_sma

actuator = SMAActuator()
response = run_sma(actuator, cycles=5)
crawler = bc.ReducedCrawler.two_bristle()
sma_gait = bc.simulate(crawler, response.stroke())
sin2_gait = bc.simulate(crawler, bc.Sin2Stroke(20.0, 20.0), cycles=5)

# Each cycle's advance predicted from its own turning points (steady regime, eq. 4.15):
# the stroke from the rest level s0 up to the peak S and back advances by S - s0 - 4 F_p/k.
bounds = sma_gait.cycle_bounds
peaks = np.array([response.s[a:b].max() for a, b in pairwise(bounds)])
rests = response.s[bounds[1:]]
c = float(crawler.fp[0] / crawler.k[0])
predicted_steady = peaks[1:] - rests[1:] - 4 * c


def main() -> None:
    adv_sma, _ = sma_gait.per_cycle()
    adv_sin, _ = sin2_gait.per_cycle()
    print("cycle durations with the SMA actuator (s):", np.round(response.cycle_durations, 2))
    print("advance per cycle, SMA  (mm):", np.round(adv_sma, 3))
    print("advance per cycle, sin2 (mm):", np.round(adv_sin, 3))
    print("steady cycles from turning points (mm):", np.round(predicted_steady, 3))


if __name__ == "__main__":
    main()
