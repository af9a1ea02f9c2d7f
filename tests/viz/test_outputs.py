"""ParaView series, animations and progress bars produce files a user can open."""

import numpy as np
import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.io.vtk import write_vtk_series
from bristlecrawler.viz.animation import write_animation
from bristlecrawler.viz.progress import sim_progress


def test_vtk_series_reads_back(tmp_path):
    import meshio

    t = np.array([0.0, 0.5, 1.0])
    base = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    pts = np.stack([base + np.array([ti, 0.0]) for ti in t])
    lines = np.array([[0, 1], [1, 2]])
    pvd = write_vtk_series(
        tmp_path,
        t,
        pts,
        lines,
        point_data={"state": np.ones((3, 3))},
        cell_data={"force": np.arange(6.0).reshape(3, 2)},
    )
    text = pvd.read_text()
    assert text.count("<DataSet") == 3 and 'timestep="0.5"' in text
    m = meshio.read(tmp_path / "crawler_00002.vtu")
    np.testing.assert_allclose(m.points[:, :2], pts[2])
    np.testing.assert_allclose(m.cell_data["force"][0], [4.0, 5.0])


def test_vtk_series_rejects_bad_connectivity(tmp_path):
    with pytest.raises(InputError, match="lines"):
        write_vtk_series(tmp_path, [0.0], np.zeros((1, 2, 2)), np.array([[0, 5]]))


def test_gif_animation(tmp_path):
    def draw(ax, i):
        ax.plot([0, i], [0, 1])

    paths = write_animation(draw, 4, tmp_path / "anim", fps=5)
    gif = paths[0]
    import imageio.v3 as iio

    frames = iio.imread(gif, index=None)
    assert frames.shape[0] == 4


def test_progress_disabled_is_silent(capsys):
    with sim_progress(10.0, enabled=False) as bar:
        bar.update(5.0, steps=3)
    assert capsys.readouterr().err == ""


def test_progress_off_a_terminal_prints_one_line_per_stage_and_mark(capsys):
    """Piped (pytest's stderr is not a terminal), a run reports each stage and each cycle
    on stderr, and nothing on stdout."""
    with sim_progress(45.0, "crawler", enabled=None, period=20.0, start=5.0) as bar:
        bar.update(0.0, stage="compiling")
        bar.update(0.0, stage="gravity step")
        bar.update(5.0, stage="")
        for t in (10.0, 24.9, 25.0, 30.0, 45.0):
            bar.update(t, steps=3)
    out, err = capsys.readouterr()
    assert out == ""
    lines = err.strip().splitlines()
    assert [x.split(" at t")[0] for x in lines[:3]] == [
        "crawler: compiling",
        "crawler: gravity step",
        "crawler: stepping",
    ]
    done = [x for x in lines if "done" in x]
    assert [x.split(",")[0] for x in done] == ["crawler: cycle 1 done", "crawler: cycle 2 done"]
    assert "t = 25/45 s" in done[0] and "steps 3" in done[0]
