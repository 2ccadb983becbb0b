"""A study's process killed outright (``kill -9``): every process it started ends by itself, on
the local engine and on a Dask ``LocalCluster`` the study's script made (docs/ensembles.md,
"Nothing lost"). Orphaned workers held about 190 MB each, and the caller's stdout and stderr,
so that a caller waiting for them hung."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

#: How long the processes of a killed study may take to end (they take well under a second).
GENEROUS_SECONDS = 60.0

DASK_STUDY = """
import sys
from pathlib import Path
import distributed
from conslaw.ensemble import run_study

if __name__ == "__main__":
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        run_study("sh-runout-shock", ["parameters.delta=uniform:22:28"], 40, Path(sys.argv[1]),
                  settings={"n_cells": 3000}, options={"scheduler": cluster}, report=print)
"""


def descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (children, their children, ...), from ``/proc``."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(parent, []).append(int(entry.name))
    found, pending = [], [pid]
    while pending:
        for child in children.get(pending.pop(), []):
            found.append(child)
            pending.append(child)
    return found


def running(pid: int) -> bool:
    """Whether ``pid`` is a process that has not ended (a zombie has)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state != "Z"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("engine", ["local", "dask"])
def test_every_process_of_a_killed_study_ends(engine: str, tmp_path: Path) -> None:
    """Once the first member is kept, SIGKILL the study's process: its workers (and the
    resource tracker, and a Dask cluster's processes) end, and the caller's pipes close."""
    if engine == "dask":
        pytest.importorskip("distributed")
    out = tmp_path / "study"
    if engine == "local":
        command = [sys.executable, "-m", "conslaw", "ensemble", "sh-runout-shock", "--samples",
                   "40", "--workers", "2", "--set", "n_cells=3000", "--vary",
                   "parameters.delta=uniform:22:28", "--out", str(out), "--no-plot"]  # fmt: skip
    else:
        command = [sys.executable, "-c", DASK_STUDY, str(out)]
    study = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    journal = out / "members.jsonl"
    started = time.monotonic()
    while not (journal.exists() and journal.read_bytes()):
        assert study.poll() is None, study.communicate()
        assert time.monotonic() - started < 300, "no member was kept"
        time.sleep(0.1)
    started_processes = descendants(study.pid)
    assert len(started_processes) >= 2, started_processes
    os.kill(study.pid, signal.SIGKILL)
    killed = time.monotonic()
    try:
        study.communicate(timeout=GENEROUS_SECONDS)  # returns once nothing holds its pipes
    except subprocess.TimeoutExpired:
        pytest.fail("a process of the killed study still holds its stdout or stderr")
    while any(running(pid) for pid in started_processes):
        if time.monotonic() - killed > GENEROUS_SECONDS:
            left = [pid for pid in started_processes if running(pid)]
            for pid in left:  # not left behind by the test either
                os.kill(pid, signal.SIGKILL)
            pytest.fail(f"processes {left} of the killed study still run")
        time.sleep(0.1)
