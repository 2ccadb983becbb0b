"""A damaged study folder (docs/ensembles.md, "Nothing lost"): the journal ``members.jsonl`` and
the study file ``study.json`` of a real interrupted study, damaged at random (hypothesis) and by
the cases of issue 46. ``--resume`` either finishes with the dataset of an uninterrupted study
or refuses in one line and leaves the folder as it was.

The interrupted study is made once per module, by a ``conslaw ensemble`` process interrupted by
SIGINT after half its members (as in ``tests/test_ensemble.py``). The resumes run in this
process on threads (:class:`ThreadEngine`, the local engine's interface on a thread pool): a
resume costs a fraction of a second instead of starting worker processes, and the members'
final states are the same bit for bit (their digests are compared).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, event, given, settings, strategies as st

from conslaw.ensemble import run_study, study as study_module
from conslaw.ensemble.dataset import read_dataset
from conslaw.ensemble.engine import LocalEngine
from conslaw.ensemble.store import line_check
from conslaw.errors import ConfigError

SCENE = "sh-runout-shock"
VARY = ["parameters.delta=uniform:22:28", "initial.height=normal:2.2:0.1"]
SETTINGS = {"n_cells": 60}
SAMPLES = 12
#: What differs between two runs of the same member: its times and its worker.
IGNORED = ["wall_seconds", "worker", "solve_seconds"]

INTERRUPTED = """
import os, signal, sys
from conslaw.cli import console_main
from conslaw.ensemble.store import StudyFolder

record = StudyFolder.record
kept = []

def record_then_interrupt(self, outcome):
    record(self, outcome)
    kept.append(outcome.index)
    if len(kept) == {at}:
        os.kill(os.getpid(), signal.SIGINT)

StudyFolder.record = record_then_interrupt
sys.argv = ["conslaw", *{argv!r}]
sys.exit(console_main())
"""


class ThreadEngine(LocalEngine):
    """The local engine on a thread pool of this process (no worker processes to start)."""

    def start(self) -> None:
        self._pool = ThreadPoolExecutor(self.workers)  # type: ignore[assignment]


def _argv(out: Path) -> list[str]:
    argv = ["ensemble", SCENE, "--samples", str(SAMPLES), "--workers", "1", "--no-plot"]
    argv += ["--set", f"n_cells={SETTINGS['n_cells']}", "--out", str(out)]
    return argv + [item for text in VARY for item in ("--vary", text)]


@pytest.fixture(scope="module")
def studies(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Any]:
    """A real interrupted study (its folder) and the dataset of the same study uninterrupted."""
    root = tmp_path_factory.mktemp("damage")
    script = INTERRUPTED.format(at=SAMPLES // 2, argv=_argv(root / "interrupted"))
    child = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert child.returncode == 130, child.stderr
    straight = subprocess.run(
        [sys.executable, "-m", "conslaw", *_argv(root / "straight")], capture_output=True
    )
    assert straight.returncode == 0, straight.stderr
    lines = (root / "interrupted" / "members.jsonl").read_bytes().splitlines()
    assert SAMPLES // 2 <= len(lines) < SAMPLES
    return root / "interrupted", read_dataset(root / "straight" / "study.nc").drop_vars(IGNORED)


@pytest.fixture
def threads() -> Iterator[None]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(study_module, "engine_for", lambda *args: ThreadEngine(2))
        yield


def snapshot(folder: Path) -> dict[str, bytes | None]:
    """Every file (its bytes) and folder (None) under ``folder``."""
    return {
        str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None)
        for p in sorted(folder.rglob("*"))
    }


def resume(folder: Path) -> tuple[Any, list[str]]:
    """``--resume`` of the study in ``folder``: the study's result and its progress lines."""
    lines: list[str] = []
    result = run_study(
        SCENE, VARY, SAMPLES, folder, settings=SETTINGS, options={"resume": True},
        report=lines.append,
    )  # fmt: skip
    return result, lines


def assert_finished_or_refused(folder: Path, straight: Any) -> str:
    """Resume ``folder``: either the uninterrupted dataset, with every member once in the
    journal, or a one-line ConfigError with the folder unchanged. Which one, as a word."""
    before = snapshot(folder)
    try:
        result, _ = resume(folder)
    except ConfigError as error:
        assert "\n" not in str(error), str(error)
        assert snapshot(folder) == before, "a refused resume changed the folder"
        return "refused"
    assert read_dataset(folder / "study.nc").drop_vars(IGNORED).identical(straight)
    assert result.dataset.drop_vars(IGNORED).identical(straight)
    return "finished"


# -- the cases of issue 46 ----------------------------------------------------------------------


def _rewrite_line(record: dict[str, Any], **changes: Any) -> bytes:
    """A journal line with ``changes`` made to a copy of ``record`` (its check kept)."""
    return json.dumps({**record, **changes}).encode()


def _damage_member_beyond(folder: Path) -> None:
    lines = (folder / "members.jsonl").read_bytes().splitlines(keepends=True)
    record = json.loads(lines[0])
    (folder / "members.jsonl").write_bytes(
        b"".join(lines) + _rewrite_line(record, member=10**6) + b"\n"
    )


def _damage_member_beyond_checked(folder: Path) -> None:
    """A line for member 1000000 whose check matches (made by hand, not by damage)."""
    lines = (folder / "members.jsonl").read_bytes().splitlines(keepends=True)
    record = {k: v for k, v in json.loads(lines[0]).items() if k != "check"}
    record["member"] = 10**6
    record["check"] = line_check(record)
    (folder / "members.jsonl").write_bytes(b"".join(lines) + json.dumps(record).encode() + b"\n")


def _damage_huge_number_checked(folder: Path) -> None:
    """A line whose check matches and whose time is an integer beyond the float range."""
    lines = (folder / "members.jsonl").read_bytes().splitlines(keepends=True)
    record = {k: v for k, v in json.loads(lines[0]).items() if k != "check"}
    record["wall_seconds"] = 10**400
    record["check"] = line_check(record)
    lines[0] = json.dumps(record).encode() + b"\n"
    (folder / "members.jsonl").write_bytes(b"".join(lines))


def _damage_summary_a_list(folder: Path) -> None:
    lines = (folder / "members.jsonl").read_bytes().splitlines(keepends=True)
    lines[1] = _rewrite_line(json.loads(lines[1]), summary=[1.0, 2.0]) + b"\n"
    (folder / "members.jsonl").write_bytes(b"".join(lines))


def _damage_journal_latin1(folder: Path) -> None:
    lines = (folder / "members.jsonl").read_bytes().splitlines(keepends=True)
    lines[0] = lines[0].replace(b'"finished"', b'"fini\xdfhed"')
    (folder / "members.jsonl").write_bytes(b"".join(lines))


def _damage_study_latin1(folder: Path) -> None:
    path = folder / "study.json"
    path.write_bytes(path.read_bytes().replace(b"sh-runout-shock", b"sh-runout-\xdfhock"))


def _damage_study_a_folder(folder: Path) -> None:
    (folder / "study.json").unlink()
    (folder / "study.json").mkdir()


def _damage_journal_a_folder(folder: Path) -> None:
    (folder / "members.jsonl").unlink()
    (folder / "members.jsonl").mkdir()


def _damage_study_a_list(folder: Path) -> None:
    (folder / "study.json").write_text("[1, 2]\n")


def _damage_study_samples_a_string(folder: Path) -> None:
    path = folder / "study.json"
    spec = json.loads(path.read_text())
    path.write_text(json.dumps({**spec, "samples": str(SAMPLES)}))


def _damage_study_deeply_nested(folder: Path) -> None:
    path = folder / "study.json"
    path.write_text(
        path.read_text().replace(
            '"extra": {', '"extra": {"x": ' + "[" * 100000 + "]" * 100000 + ", ", 1
        )
    )


def _damage_journal_deeply_nested(folder: Path) -> None:
    with open(folder / "members.jsonl", "a") as journal:
        journal.write("[" * 100000 + "]" * 100000 + "\n")


#: (damage, "finished" or "refused", a fragment of the note or the refusal)
CASES = [
    (_damage_member_beyond, "finished", "its check does not match"),
    (_damage_member_beyond_checked, "finished", "member 1000000 is not one of the study's 0 to 11"),
    (_damage_summary_a_list, "finished", "its check does not match"),
    (_damage_huge_number_checked, "finished", "int too large to convert to float"),
    (_damage_journal_latin1, "finished", "can't decode byte 0xdf"),
    (_damage_journal_deeply_nested, "finished", "line"),
    (_damage_study_latin1, "refused", "study.json' is damaged ('utf-8' codec can't decode"),
    (_damage_study_a_folder, "refused", "cannot read", ),
    (_damage_journal_a_folder, "refused", "members.jsonl' (Is a directory)"),
    (_damage_study_a_list, "refused", "study.json' is damaged (expected a JSON object, got list)"),
    (_damage_study_samples_a_string, "refused", "samples: expected an integer, got '12'"),
    (_damage_study_deeply_nested, "refused", "study.json' is damaged"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("damage", "expected", "fragment"), CASES, ids=[c[0].__name__[8:] for c in CASES]
)
def test_a_damaged_folder_resumes_or_is_refused_in_one_line(
    damage: Any,
    expected: str,
    fragment: str,
    studies: tuple[Path, Any],
    threads: None,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Each case of issue 46 through ``conslaw ensemble --resume``: a damaged journal line is
    skipped with one note and its member run again (the dataset of the uninterrupted study); a
    damaged or unreadable study file, or a journal that cannot be read, is one line, exit 2,
    nothing changed."""
    from conslaw.cli import main

    folder = tmp_path / "study"
    shutil.copytree(studies[0], folder)
    damage(folder)
    before = snapshot(folder)
    code = main([*_argv(folder), "--resume"])
    out, err = capsys.readouterr()
    if expected == "refused":
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 1 and lines[0].startswith("conslaw: error: "), err
        assert fragment in lines[0], lines[0]
        assert snapshot(folder) == before
        return
    assert code == 0, err
    notes = [line for line in out.splitlines() if "damaged line" in line]
    assert len(notes) == 1 and fragment in notes[0], out
    assert read_dataset(folder / "study.nc").drop_vars(IGNORED).identical(studies[1])
    members = [json.loads(line).get("member") for line in _intact(folder)]
    assert sorted(members) == list(range(SAMPLES))


def _intact(folder: Path) -> list[bytes]:
    """The journal lines a resume keeps (the damaged ones left out)."""
    from conslaw.ensemble.store import _outcome_from

    kept = []
    for line in (folder / "members.jsonl").read_bytes().splitlines():
        try:
            _outcome_from(line, SAMPLES)
        except (ValueError, TypeError, RecursionError, ArithmeticError):
            continue
        kept.append(line)
    return kept


def test_a_journal_of_an_earlier_conslaw_without_checks_is_run_again(
    studies: tuple[Path, Any], threads: None, tmp_path: Path
) -> None:
    """Lines without a check (written before checks were) are skipped: their members run
    again, and the study finishes as the uninterrupted one."""
    folder = tmp_path / "study"
    shutil.copytree(studies[0], folder)
    journal = folder / "members.jsonl"
    lines = [json.loads(line) for line in journal.read_bytes().splitlines()]
    journal.write_text("".join(json.dumps({k: v for k, v in r.items() if k != "check"}) + "\n"
                               for r in lines))  # fmt: skip
    result, notes = resume(folder)
    assert result.ran == SAMPLES
    assert any(f"skipped {len(lines)} damaged line(s)" in note for note in notes), notes
    assert result.dataset.drop_vars(IGNORED).identical(studies[1])


# -- damage at random --------------------------------------------------------------------------

#: JSON values a damaged field may hold.
JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-(2**70), 2**70) | st.floats() | st.text(max_size=8),
    lambda inner: (
        st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner, max_size=3)
    ),
    max_leaves=6,
)


@st.composite
def byte_damage(draw: st.DrawFn, data: bytes) -> bytes:
    """``data`` with bytes replaced, deleted, inserted or cut off."""
    kind = draw(st.sampled_from(["replace", "delete", "insert", "cut", "newline"]))
    at = draw(st.integers(0, max(len(data) - 1, 0)))
    if kind == "replace":
        return data[:at] + draw(st.binary(min_size=1, max_size=4)) + data[at + 1 :]
    if kind == "delete":
        return data[:at] + data[at + draw(st.integers(1, 40)) :]
    if kind == "insert":
        return data[:at] + draw(st.binary(min_size=1, max_size=8)) + data[at:]
    if kind == "newline":
        return data[:at] + b"\n" + data[at:]
    return data[:at]


@st.composite
def field_damage(draw: st.DrawFn, data: bytes) -> bytes:
    """``data``, a JSON object, with a field set to another value, removed or added (the rest
    of the text, a journal line's check too, as it was)."""
    try:
        record = json.loads(data)
    except ValueError:
        record = None
    if not isinstance(record, dict) or not record:
        return draw(byte_damage(data))  # damaged before: damage its bytes
    keys = sorted(record)
    kind = draw(st.sampled_from(["set", "remove", "add"]))
    if kind == "set":
        record[draw(st.sampled_from(keys))] = draw(JSON_VALUES)
    elif kind == "remove":
        record.pop(draw(st.sampled_from(keys)))
    else:
        record[draw(st.text(min_size=1, max_size=6))] = draw(JSON_VALUES)
    return json.dumps(record).encode()


@st.composite
def journal_damage(draw: st.DrawFn, data: bytes) -> bytes:
    """The journal ``data`` with one of its lines (or the whole) damaged, a line repeated,
    removed, swapped or added."""
    lines = data.splitlines(keepends=True)
    kind = draw(st.sampled_from(["bytes", "field", "repeat", "remove", "swap", "add", "whole"]))
    if not lines:
        return draw(byte_damage(data))
    at = draw(st.integers(0, len(lines) - 1))
    if kind == "bytes":
        lines[at] = draw(byte_damage(lines[at]))
    elif kind == "field":
        lines[at] = draw(field_damage(lines[at].rstrip(b"\n"))) + b"\n"
    elif kind == "repeat":
        lines.insert(draw(st.integers(0, len(lines))), lines[at])
    elif kind == "remove":
        del lines[at]
    elif kind == "swap":
        other = draw(st.integers(0, len(lines) - 1))
        lines[at], lines[other] = lines[other], lines[at]
    elif kind == "add":
        lines.append(json.dumps(draw(JSON_VALUES)).encode() + b"\n")
    else:
        return draw(byte_damage(data))
    return b"".join(lines)


def _damage_at_random(folder: Path, draw: st.DrawFn, name: str) -> None:
    path = folder / name
    data = path.read_bytes()
    if name == "members.jsonl":
        path.write_bytes(draw(journal_damage(data)))
    elif draw(st.booleans()):
        path.write_bytes(draw(byte_damage(data)))
    else:
        path.write_bytes(draw(field_damage(data)))


@pytest.mark.slow
@settings(
    max_examples=300,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(data=st.data())
def test_a_folder_damaged_at_random_finishes_equal_or_is_refused_in_one_line(
    data: st.DataObject, studies: tuple[Path, Any], threads: None, tmp_path: Path
) -> None:
    """A real interrupted study's journal and study file damaged at random (bytes replaced,
    inserted, deleted or cut off; fields set to other JSON values, removed or added; lines
    repeated, removed, swapped or added; one to three damages): ``--resume`` finishes with the
    uninterrupted study's dataset, or refuses in one line and changes nothing; with only the
    journal damaged, it finishes."""
    folder = Path(tempfile.mkdtemp(dir=tmp_path)) / "study"
    shutil.copytree(studies[0], folder)
    damaged = set()
    for _ in range(data.draw(st.integers(1, 3), label="damages")):
        name = data.draw(st.sampled_from(["members.jsonl", "study.json"]), label="file")
        _damage_at_random(folder, data.draw, name)
        damaged.add(name)
    outcome = assert_finished_or_refused(folder, studies[1])
    event(f"{outcome} ({', '.join(sorted(damaged))} damaged)")
    if "study.json" not in damaged:  # a damaged journal line is skipped, never refused
        assert outcome == "finished"
    shutil.rmtree(folder.parent)
