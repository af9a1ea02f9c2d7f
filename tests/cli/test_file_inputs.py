"""Input files that are not what they should be: a FIFO (which would block a reader
forever), a device, a file of the wrong shape. Each is one line and exit 2, at once."""

import os
import threading

import numpy as np
import pytest


class _Unblocker:
    """Opens a FIFO for writing after a while, so that a reader stuck on it goes on (and
    the test fails rather than hangs); ``fired`` says whether it had to."""

    def __init__(self, fifo):
        self.fired = False
        self._fifo = fifo
        self._timer = threading.Timer(10.0, self._open)
        self._timer.start()

    def _open(self):
        self.fired = True
        os.close(os.open(self._fifo, os.O_WRONLY | os.O_NONBLOCK))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._timer.cancel()


@pytest.mark.parametrize(
    "args",
    [
        ["reduced", "--texture", "{fifo}"],
        ["reduced", "--history", "{fifo}"],
        ["reduced", "--texture", "/dev/zero"],
        ["reduced", "--history", "/dev/zero"],
        ["simulate", "{fifo}.toml"],
    ],
    ids=["texture-fifo", "history-fifo", "texture-device", "history-device", "scenario-fifo"],
)
def test_a_fifo_or_device_as_an_input_file_is_one_line_at_once(tmp_path, run_cli, args):
    fifo = str(tmp_path / "in")
    path = args[-1].format(fifo=fifo)
    if path.startswith(fifo):
        os.mkfifo(path)
    args = [*args[:-1], path, "--out", str(tmp_path / "o")]
    with _Unblocker(path) if path.startswith(fifo) else _NoTimer() as timer:
        code, out, err = run_cli(args)
    assert not timer.fired
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "not a regular file" in err
    assert not (tmp_path / "o").exists()


class _NoTimer:
    fired = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        pass


def test_a_tdms_channel_of_text_is_one_line(tmp_path, run_cli):
    from nptdms import ChannelObject, TdmsWriter

    path = tmp_path / "r.tdms"
    t = np.linspace(0.0, 1.0, 50)
    with TdmsWriter(str(path)) as w:
        w.write_segment(
            [
                ChannelObject("g", "time", t),
                ChannelObject("g", "left", np.array(["a"] * 50)),
                ChannelObject("g", "right", t),
            ]
        )
    code, out, err = run_cli(["analyze", str(path), "--out", str(tmp_path / "o")])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "does not hold numbers" in err


@pytest.mark.parametrize("suffix", [".csv", ".tdms"])
def test_a_fifo_as_a_recording_is_named_as_such(tmp_path, run_cli, suffix):
    path = tmp_path / f"r{suffix}"
    os.mkfifo(path)
    with _Unblocker(str(path)) as timer:
        code, out, err = run_cli(["analyze", str(path), "--out", str(tmp_path / "o")])
    assert not timer.fired
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "it is a FIFO, not a regular file" in err
