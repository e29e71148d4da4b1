"""``orthoglide_play.py``: its checks and its sequence, against a stand-in ``linuxcnc`` module.

The script runs in LinuxCNC's Python; here its ``linuxcnc`` module and its
``halcmd``/``halstreamer`` calls are stand-ins that record what it asks. The
script in a real session: ``tests/controller/test_stream.py``.
"""

from __future__ import annotations

import subprocess
import sys
import types
from pathlib import Path
from typing import Any

import pytest

from orthoglide_pin.controller import PLAYER, player_text

#: The stand-in's task states (LinuxCNC's values).
ESTOP_RESET, OFF, ON = 2, 3, 4
#: Exit status of a refusal.
REFUSED = 2


class Machine:
    """A stand-in LinuxCNC: homed or not, joints somewhere, the streamer's FIFO."""

    def __init__(self, joints: tuple[float, float, float], homed: bool = True) -> None:
        self.joint_actual_position = joints
        self.homed = (homed, homed, homed)
        self.interp_state = 1
        self.task_state, self.enabled = ON, True
        self.calls: list[Any] = []
        self.queued = 0

    def module(self) -> types.ModuleType:
        machine = self
        mod = types.ModuleType("linuxcnc")
        mod.STATE_ESTOP_RESET, mod.STATE_OFF, mod.STATE_ON = ESTOP_RESET, OFF, ON  # type: ignore[attr-defined]
        mod.INTERP_IDLE = 1  # type: ignore[attr-defined]

        class Command:
            def state(self, state: int) -> None:
                machine.calls.append(("state", state))
                machine.task_state = ESTOP_RESET if state == OFF else state
                machine.enabled = state == ON

        class Stat:
            def __getattr__(self, name: str) -> Any:
                return getattr(machine, name)

            def poll(self) -> None:
                pass

        mod.command, mod.stat = Command, Stat  # type: ignore[attr-defined]
        return mod

    def run(self, args: list[str], **_: Any) -> subprocess.CompletedProcess[str]:
        self.calls.append(tuple(args))
        if args[0] == "halstreamer":
            assert self.task_state != ON and not self.enabled  # the machine off first
            self.queued = 3  # three polls until the FIFO is empty
            return subprocess.CompletedProcess(args, 0, "", "")
        self.queued = max(self.queued - 1, 0)
        return subprocess.CompletedProcess(args, 0, "FALSE\n" if self.queued else "TRUE\n", "")


def _play(monkeypatch: pytest.MonkeyPatch, machine: Machine, stream: Path) -> None:
    monkeypatch.setitem(sys.modules, "linuxcnc", machine.module())
    space: dict[str, Any] = {"__name__": "player"}
    exec(compile(player_text(), PLAYER, "exec"), space)
    space["subprocess"] = types.SimpleNamespace(run=machine.run)
    space["time"] = types.SimpleNamespace(time=__import__("time").time, sleep=lambda _: None)
    space["main"](str(stream))


@pytest.fixture
def stream(tmp_path: Path) -> Path:
    path = tmp_path / "plan.stream"
    path.write_text("0.000000000 0.000000000 0.000000000\n0.1 0.0 -0.1\n")
    return path


def test_plays_with_the_machine_off_then_on(monkeypatch: pytest.MonkeyPatch, stream: Path) -> None:
    machine = Machine((0.0, 0.0, 0.0))
    _play(monkeypatch, machine, stream)
    states = [c for c in machine.calls if c[0] == "state"]
    assert states == [("state", OFF), ("state", ON)]
    order = [c[0] for c in machine.calls]
    assert order.index("halstreamer") < machine.calls.index(("state", ON))
    assert ("halstreamer", str(stream)) in machine.calls
    assert machine.task_state == ON and machine.queued == 0  # on once the FIFO is empty


@pytest.mark.parametrize(
    ("machine", "message"),
    [
        (Machine((1.0, 0.0, 0.0)), "the joints are at [1.0, 0.0, 0.0] mm"),
        (Machine((0.0, 0.0, 0.0), homed=False), "home the joints first"),
    ],
)
def test_refuses_before_moving(
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    stream: Path,
    machine: Machine,
    message: str,
) -> None:
    with pytest.raises(SystemExit) as stop:
        _play(monkeypatch, machine, stream)
    assert stop.value.code == REFUSED
    err = capsys.readouterr().err
    assert err.startswith(f"{PLAYER}: ") and message in err and err.count("\n") == 1
    assert not [c for c in machine.calls if c[0] in ("state", "halstreamer")]


def test_refuses_a_running_program(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], stream: Path
) -> None:
    machine = Machine((0.0, 0.0, 0.0))
    machine.interp_state = 2
    with pytest.raises(SystemExit):
        _play(monkeypatch, machine, stream)
    assert "a program is running" in capsys.readouterr().err
    assert machine.calls == []
