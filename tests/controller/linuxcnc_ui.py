#!/usr/bin/env python3
"""Display program of the headless LinuxCNC tests (run by ``linuxcnc``, system Python).

Resets E-stop, switches the machine on, homes the joints, then plays each
stream of ``OG_STREAMS`` with the configuration's ``orthoglide_play.py`` (the
optimal route: the machine off, ``halstreamer`` feeds the configuration's
``streamer``, whose positions the joints take while it plays; the machine on
again at its end), has it refuse ``OG_REFUSED_STREAM`` (``refused.json``: exit
status, message, how far the joints moved), then runs each program of
``OG_PROGRAMS`` (paths separated by ``:``, the certified route). Meanwhile
``halsampler`` records the sampler's channels (the joints' positions, every
servo period, the sampler enabled meanwhile) into ``OG_OUT/<n>.samples``
(``s<n>.samples`` for stream ``n``); the status is polled, and pairs (joint
positions, pose) go to ``OG_OUT/<n>.json`` (``s<n>.json``) with the run's time.
Any failure is written to ``OG_OUT/error.txt``. Exits when done, which stops
LinuxCNC.
"""

import json
import os
import subprocess
import sys
import time
import traceback

import linuxcnc

OUT = os.environ["OG_OUT"]
TIMEOUT = float(os.environ.get("OG_TIMEOUT", "120"))


def wait(stat, what, test, timeout=20.0):
    end = time.time() + timeout
    while time.time() < end:
        stat.poll()
        if test(stat):
            return
        time.sleep(0.01)
    raise RuntimeError(
        f"timed out waiting for {what} (task state {stat.task_state}, mode {stat.task_mode}, "
        f"interpreter {stat.interp_state}, motion enabled {stat.enabled})"
    )


def drain(errors):
    out = []
    while True:
        e = errors.poll()
        if not e:
            return out
        out.append(e[1])


def record(s, errors, name, path, begin, ended):
    """Sample the joints while ``begin()`` starts a run until ``ended()``; write the results."""
    samples = open(os.path.join(OUT, f"{name}.samples"), "w")  # noqa: SIM115
    sampler = subprocess.Popen(["halsampler", "-t"], stdout=samples)
    subprocess.run(["halcmd", "setp", "sampler.0.enable", "1"], check=True)
    pairs, rests = [], []
    start = time.time()
    begin()
    while True:
        s.poll()
        pairs.append([list(s.joint_actual_position[:3]), list(s.actual_position[:3])])
        if ended(s):
            break
        if time.time() - start > TIMEOUT:
            raise RuntimeError(f"{path} did not end in {TIMEOUT} s")
        time.sleep(0.003)
    elapsed = time.time() - start
    time.sleep(0.1)
    subprocess.run(["halcmd", "setp", "sampler.0.enable", "0"], check=True)
    time.sleep(0.3)
    sampler.terminate()
    sampler.wait(5)
    samples.close()
    s.poll()
    rests.append([list(s.position[:3]), list(s.actual_position[:3])])
    msgs = drain(errors)
    with open(os.path.join(OUT, f"{name}.json"), "w") as f:
        json.dump({"pairs": pairs, "rests": rests, "elapsed": elapsed, "errors": msgs}, f)


def run_program(c, s, errors, n, path):
    c.mode(linuxcnc.MODE_AUTO)
    c.wait_complete()
    c.program_open(path)
    c.wait_complete()

    def begin():
        c.auto(linuxcnc.AUTO_RUN, 0)
        wait(s, "the program to start", lambda st: st.interp_state != linuxcnc.INTERP_IDLE, 5)

    def ended(st):
        return st.interp_state == linuxcnc.INTERP_IDLE and st.queue == 0

    record(s, errors, str(n), path, begin, ended)


def play_stream(s, errors, n, path):
    """The optimal route: the configuration's orthoglide_play.py plays the stream."""
    player = []
    log = open(os.path.join(OUT, f"s{n}.player"), "w")  # noqa: SIM115

    def begin():
        command = [sys.executable, "orthoglide_play.py", path]
        player.append(subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT))

    def ended(st):
        return player[0].poll() is not None

    record(s, errors, f"s{n}", path, begin, ended)
    log.close()
    if player[0].returncode != 0:
        with open(log.name) as f:
            raise RuntimeError(f"orthoglide_play.py {path}: {f.read()}")
    s.poll()
    if s.task_state != linuxcnc.STATE_ON or not all(s.homed[:3]):
        raise RuntimeError("the machine is not on and homed after the stream")


def refuse_stream(s, path):
    """A stream that does not start where the joints are: refused, nothing moved."""
    s.poll()
    before = list(s.joint_actual_position[:3])
    done = subprocess.run(
        [sys.executable, "orthoglide_play.py", path], capture_output=True, text=True
    )
    time.sleep(0.1)
    s.poll()
    after = list(s.joint_actual_position[:3])
    with open(os.path.join(OUT, "refused.json"), "w") as f:
        json.dump(
            {
                "status": done.returncode,
                "stderr": done.stderr,
                "moved": max(abs(a - b) for a, b in zip(before, after, strict=True)),
                "on": s.task_state == linuxcnc.STATE_ON,
            },
            f,
        )


def main():
    c, s, errors = linuxcnc.command(), linuxcnc.stat(), linuxcnc.error_channel()
    c.state(linuxcnc.STATE_ESTOP_RESET)
    c.state(linuxcnc.STATE_ON)
    wait(s, "machine on", lambda st: st.task_state == linuxcnc.STATE_ON)
    c.mode(linuxcnc.MODE_MANUAL)
    c.wait_complete()
    c.teleop_enable(0)
    c.wait_complete()
    c.home(-1)
    wait(s, "homing", lambda st: all(st.homed[:3]))
    drain(errors)
    streams = [p for p in os.environ.get("OG_STREAMS", "").split(":") if p]
    for n, path in enumerate(streams):
        play_stream(s, errors, n, path)
    if os.environ.get("OG_REFUSED_STREAM"):
        refuse_stream(s, os.environ["OG_REFUSED_STREAM"])
    programs = [p for p in os.environ.get("OG_PROGRAMS", "").split(":") if p]
    for n, path in enumerate(programs):
        run_program(c, s, errors, n, path)
    if os.environ.get("OG_MDI"):
        c.mode(linuxcnc.MODE_MDI)
        c.wait_complete()
        rests = []
        with open(os.environ["OG_MDI"]) as f:
            lines = f.read().splitlines()
        for line in lines:
            c.mdi(line.strip())
            c.wait_complete(10)
            wait(s, "the move", lambda st: st.interp_state == linuxcnc.INTERP_IDLE)
            s.poll()
            rests.append(
                [
                    list(s.position[:3]),
                    list(s.joint_actual_position[:3]),
                    list(s.actual_position[:3]),
                ]
            )
        with open(os.path.join(OUT, "mdi.json"), "w") as f:
            json.dump({"rests": rests, "errors": drain(errors)}, f)
    with open(os.path.join(OUT, "done"), "w") as f:
        f.write("ok\n")


try:
    main()
except Exception:
    with open(os.path.join(OUT, "error.txt"), "w") as f:
        f.write(traceback.format_exc())
    sys.exit(1)
