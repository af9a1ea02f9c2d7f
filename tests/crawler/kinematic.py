"""A kinematic stand-in for a finite-element run: the reduced model's motion drawn as a
crawler (body, rigid links, straight bristles), for testing outputs without the FE solver."""

import numpy as np

from bristlecrawler.crawler.history import TIP_SLIP, TIP_STICK, CrawlerHistory
from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, simulate


def kinematic_history(cycles=2, samples=80, height=12.0, link=8.0) -> CrawlerHistory:
    res = simulate(ReducedCrawler.two_bristle(), Sin2Stroke(20.0, 20.0), cycles, samples)
    m = res.t.size
    y = np.full(m, height)
    left = np.column_stack([res.X[:, 0], y])
    right = np.column_stack([res.X[:, 1], y])
    tips = np.stack([np.column_stack([res.x[:, i] - 3.0, np.zeros(m)]) for i in (0, 1)], axis=1)
    state = np.where(res.state != 0, TIP_SLIP, TIP_STICK)
    fc = res.force[:, 1]
    work = res.work
    energies = {"elastic": res.elastic_energy, "friction": res.dissipation, "external": work}
    frames = np.arange(0, m, 2)
    nodes = []
    for f in frames:
        clamp_l, clamp_r = left[f] - [0, link], right[f] - [0, link]
        nodes.append([left[f], right[f], clamp_l, clamp_r, tips[f, 0], tips[f, 1]])
    lines = np.array([[0, 1], [0, 2], [1, 3], [2, 4], [3, 5]])
    xs = np.linspace(-10, 120, 261)
    sub = np.column_stack([xs, np.where(np.mod(xs, 2.0) < 1.0, -0.25, 0.0)])
    return CrawlerHistory(
        t=res.t,
        s=res.shortening[:, 0],
        left=left,
        right=right,
        connector_force=fc,
        connector_work=work,
        tip_position=tips,
        tip_state=state,
        energies=energies,
        frame_t=res.t[frames],
        frame_nodes=np.asarray(nodes),
        lines=lines,
        line_kind=np.array([0, 1, 1, 2, 2]),
        substrate_xy=sub,
        period=20.0,
        cycles=cycles,
        stats={"steps": m},
        node_thickness=np.array([0.0, 0.0, 3.0, 3.0, 0.5, 0.5]),
    )
