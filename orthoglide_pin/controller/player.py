"""The optimal route in a LinuxCNC session: ``orthoglide_play.py``, written with the configuration.

The configuration's ``orthoglide_sim.hal`` carries HAL's ``streamer``, whose
positions the joints take while it plays
(:func:`~orthoglide_pin.controller.configuration.hal_text`). The script of
:func:`player_text` plays a stream (``plan.stream``,
:mod:`~orthoglide_pin.controller.stream`) on the running session: it checks
that the joints are homed, that no program runs and that the stream starts
where the joints are (to :data:`START_TOL_MM`), turns the machine off (motion
disabled, its command then tracks the joints), runs ``halstreamer``, waits
until the streamer has played the last line, and turns the machine on again
if it was on. It runs with the Python of LinuxCNC (its ``linuxcnc`` module):
``python3 orthoglide_play.py plan.stream``. A refusal is one line on stderr
and exit status 2; before ``halstreamer`` starts, nothing has moved.
"""

from __future__ import annotations

from typing import Final

#: The script's file name in the configuration.
PLAYER: Final[str] = "orthoglide_play.py"
#: How far the stream's first line may be from the joints [mm].
START_TOL_MM: Final[float] = 1e-6


def player_text() -> str:
    """The script that plays a stream on the running LinuxCNC session (see the module)."""
    return f'''#!/usr/bin/env python3
"""Play a joint stream (orthoglide plan --linuxcnc) on the running LinuxCNC session.

    python3 {PLAYER} [plan.stream]

The joints homed, no program running, the stream starting where the joints
are: turns the machine off, plays the stream through the streamer of
orthoglide_sim.hal (the joints follow it; LinuxCNC checks nothing of the
motion meanwhile, the plan holds the limits), waits for its last line, and
turns the machine on again if it was on. Exit status 2 on a refusal.
"""

import subprocess
import sys
import time

import linuxcnc

START_TOL_MM = {START_TOL_MM!r}
OFF = (linuxcnc.STATE_OFF, linuxcnc.STATE_ESTOP_RESET)


def refuse(message):
    print(f"{PLAYER}: {{message}}", file=sys.stderr)
    sys.exit(2)


def wait(stat, what, test, timeout=20.0):
    end = time.time() + timeout
    while time.time() < end:
        stat.poll()
        if test(stat):
            return
        time.sleep(0.01)
    refuse(f"timed out waiting for {{what}}")


def turn_on(command, stat, tries=10, each=2.0):
    # LinuxCNC's task may drop a state command that comes while it is still
    # settling the machine off: ask again until the machine is on.
    for _ in range(tries):
        command.state(linuxcnc.STATE_ON)
        end = time.time() + each
        while time.time() < end:
            stat.poll()
            if stat.task_state == linuxcnc.STATE_ON:
                return
            time.sleep(0.01)
    refuse("timed out waiting for the machine on")


def empty():
    done = subprocess.run(
        ["halcmd", "-s", "getp", "streamer.0.empty"], capture_output=True, text=True
    )
    return done.stdout.strip() == "TRUE"


def main(path):
    command, stat = linuxcnc.command(), linuxcnc.stat()
    stat.poll()
    if not all(stat.homed[:3]):
        refuse("home the joints first")
    if stat.interp_state != linuxcnc.INTERP_IDLE:
        refuse("a program is running")
    try:
        with open(path) as f:
            first = [float(w) for w in f.readline().split()]
    except (OSError, ValueError) as e:
        refuse(f"cannot read {{path}}: {{e}}")
    joints = list(stat.joint_actual_position[:3])
    if len(first) != 3 or max(abs(a - b) for a, b in zip(joints, first)) > START_TOL_MM:
        refuse(f"{{path}} starts at {{first}} mm, the joints are at {{joints}} mm")
    if not empty():
        refuse("the streamer is playing another stream")
    was_on = stat.task_state == linuxcnc.STATE_ON
    command.state(linuxcnc.STATE_OFF)
    wait(stat, "the machine off", lambda st: st.task_state in OFF and not st.enabled)
    played = subprocess.run(["halstreamer", path])
    while not empty():  # the FIFO's last lines (4 s at most) still play
        time.sleep(0.05)
    if played.returncode != 0:
        refuse(f"halstreamer {{path}} failed (exit status {{played.returncode}}), machine off")
    if was_on:
        turn_on(command, stat)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "plan.stream")
'''
