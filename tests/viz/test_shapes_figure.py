"""The deformed-shapes figure is legible where the report shows it (860 px wide): every
tick label and axis label of at least 10 px there. Drawn from a stand-in history of two
straight bristles (no FE run)."""

import types

import matplotlib
import numpy as np

matplotlib.use("Agg")

from bristlecrawler.viz.crawler import plot_shapes

REPORT_PX = 860  # the width the report shows a figure at (render.STYLE's img max-width)


def _history(cycles: int = 2) -> types.SimpleNamespace:
    """Two bristles of four elements under a 100 mm body, 12 frames, grooves of 2 mm."""
    tip = np.array([[-3.0, 0.0], [-2.25, 0.75], [-1.5, 1.5], [-0.75, 2.25], [0.0, 3.0]])
    shift = np.array([100.0, 0.0])
    nodes = np.concatenate([tip, tip + shift, [[0.0, 8.0], [100.0, 8.0]]])
    lines = [(i, i + 1) for i in range(4)] + [(i, i + 1) for i in range(5, 9)]
    kinds = [2] * 8
    lines += [(4, 10), (9, 11), (10, 11)]
    kinds += [1, 1, 0]
    t = np.linspace(0.0, 0.4 * cycles, 12)
    x = np.arange(-10.0, 112.0, 1.0)
    groove = np.where(np.floor(x / 1.0) % 2 == 0, 0.0, -0.3)
    return types.SimpleNamespace(
        cycles=cycles,
        period=0.4,
        t=t,
        s=np.sin(np.pi * t / 0.4) ** 2,
        frame_t=t,
        frame_nodes=np.repeat(nodes[None], t.size, axis=0),
        lines=np.array(lines),
        line_kind=np.array(kinds),
        node_thickness=np.full(len(nodes), 0.6),
        substrate_xy=np.stack([x, groove], axis=1),
        left=np.repeat(nodes[None, 0], t.size, axis=0),
        right=np.repeat(nodes[None, 5], t.size, axis=0),
        bristle_chains=lambda: [np.arange(4, -1, -1), np.arange(9, 4, -1)],
    )


def test_every_label_is_legible_at_the_reports_width():
    fig = plot_shapes(_history())
    px_per_pt = REPORT_PX / (fig.get_figwidth() * 72.0)
    sizes = []
    for ax in fig.axes:
        labels = [*ax.get_xticklabels(), *ax.get_yticklabels(), ax.xaxis.label, ax.yaxis.label]
        sizes += [lab.get_fontsize() for lab in labels if lab.get_text()]
    assert sizes and min(sizes) * px_per_pt >= 10.0, min(sizes) * px_per_pt
