"""A study's folder: what was asked (``study.json``), a journal of the finished members
(``members.jsonl``, one line each, written as each member arrives), the members' maps
(``fields/member-NNNNNN.npz``) and the labelled dataset built from them (docs/ensembles.md,
"Nothing lost").

The journal is what a resumed study reads: a member with a line there is not run again. A line
cut short by a killed process is dropped (and cut off the file) on the next start; a member's
maps are in place before its line is written. The folder is held with an advisory lock while a
study writes into it, so that two studies never mix their members.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from conslaw.ensemble.member import STATUSES, MemberOutcome
from conslaw.errors import ConfigError, shown
from conslaw.output.files import atomic_write_bytes, hold_folder, prepare_output_dir

SPEC_FILE = "study.json"
JOURNAL_FILE = "members.jsonl"
FIELDS_FOLDER = "fields"


@dataclass(frozen=True)
class StudySpec:
    """What a study runs: the scene, the keys set for all members, the varied keys, the
    design (everything that decides the members), and what is kept of each.

    Attributes
    ----------
    scene : str
        A built-in scene name or a scene file's absolute path.
    settings : dict
        Scene keys set for every member (``--set``).
    vary : list of str
        The variations as given (``KEY=DISTRIBUTION:ARGS``).
    design : str
    samples : int
    seed : int
    fields : bool
        Keep each member's maps.
    depth_threshold : float or None
        Covered depth for the 1D summary figures (None: relative default).
    scene_sha256 : str
        SHA-256 of the scene file's bytes: a resumed study whose scene file changed is refused.
    versions : dict
        conslaw's and scipy's versions (scipy draws the members): the same on resume.
    """

    scene: str
    settings: dict[str, Any]
    vary: list[str]
    design: str
    samples: int
    seed: int
    fields: bool = False
    depth_threshold: float | None = None
    scene_sha256: str = ""
    versions: dict[str, str] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not self.versions:
            import scipy

            from conslaw import __version__

            self.versions.update(conslaw=__version__, scipy=scipy.__version__)

    def to_json(self) -> str:
        """The spec as a JSON document (``study.json``)."""
        return json.dumps(asdict(self), indent=2, sort_keys=True) + "\n"

    @classmethod
    def from_json(cls, data: bytes, where: Path) -> StudySpec:
        """Read ``study.json`` (its bytes); a ConfigError naming the file and the first field
        that is not what a study writes (:func:`_spec_fields`)."""
        try:
            fields = _spec_fields(json.loads(data.decode("utf-8")))
        except (ValueError, TypeError, RecursionError) as error:
            raise ConfigError(
                f"'{where}' is damaged ({error}): restore it, or move the folder aside and run "
                "the study again"
            ) from None
        return cls(**fields)

    def difference(self, other: StudySpec) -> str | None:
        """The first field in which ``other`` asks for another study, as text, or None."""
        mine, theirs = asdict(self), asdict(other)
        for key in mine:
            if key != "extra" and mine[key] != theirs[key]:
                return f"{key}: {mine[key]!r} there, {theirs[key]!r} now"
        return None


#: The fields of ``study.json``: the types each may hold, and how to say so.
_SPEC_TYPES: dict[str, tuple[tuple[type, ...], str]] = {
    "scene": ((str,), "a string"), "settings": ((dict,), "an object"),
    "vary": ((list,), "a list"), "design": ((str,), "a string"), "samples": ((int,), "an integer"),
    "seed": ((int,), "an integer"), "fields": ((bool,), "true or false"),
    "depth_threshold": ((float, int, type(None)), "a number or null"),
    "scene_sha256": ((str,), "a string"), "versions": ((dict,), "an object"),
    "extra": ((dict,), "an object"),
}  # fmt: skip


def _spec_fields(document: Any) -> dict[str, Any]:
    """The fields of a ``study.json`` document, each of its type; a ValueError naming the first
    that is missing, unknown or of another type."""
    if not isinstance(document, dict):
        raise ValueError(f"expected a JSON object, got {type(document).__name__}")
    for key in document:
        if key not in _SPEC_TYPES:
            raise ValueError(f"unknown field {shown(key)}")
    for key, (types, expected) in _SPEC_TYPES.items():
        if key not in document:
            raise ValueError(f"field '{key}' missing")
        value = document[key]
        if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
            raise ValueError(f"{key}: expected {expected}, got {shown(value)}")
    if not all(isinstance(text, str) for text in document["vary"]):
        raise ValueError(f"vary: expected a list of strings, got {shown(document['vary'])}")
    return document


#: The fields of a journal line, in the order they are written (``check`` last).
_LINE_FIELDS = ("member", "status", "message", "digest", "wall_seconds", "worker", "summary")


def line_check(record: dict[str, Any]) -> str:
    """The check of a journal line: the first 16 hex digits of the SHA-256 of its other fields
    as JSON (sorted keys), so that a line changed after it was written is found."""
    text = json.dumps(record, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _outcome_line(outcome: MemberOutcome) -> str:
    record: dict[str, Any] = {
        "member": outcome.index,
        "status": outcome.status,
        "message": outcome.message,
        "digest": outcome.digest,
        "wall_seconds": outcome.wall_seconds,
        "worker": outcome.worker,
        "summary": outcome.summary,
    }
    record["check"] = line_check(record)
    return json.dumps(record, allow_nan=True) + "\n"


def _outcome_from(line: bytes, samples: int) -> MemberOutcome:
    """A journal line's member; a ValueError saying how the line is damaged (not UTF-8, not
    JSON, a field missing or of another type, its check not matching, a member beyond the
    study)."""
    record = json.loads(line.decode("utf-8"))
    if not isinstance(record, dict):
        raise ValueError(f"expected a JSON object, got {type(record).__name__}")
    unknown = set(record) - {*_LINE_FIELDS, "check"}
    missing = [key for key in (*_LINE_FIELDS, "check") if key not in record]
    if unknown or missing:
        raise ValueError(
            f"field {shown(sorted(unknown or missing)[0])} {'unknown' if unknown else 'missing'}"
        )
    check = record.pop("check")
    if check != line_check(record):
        raise ValueError("its check does not match its content")
    member, summary = record["member"], record["summary"]
    if not (isinstance(member, int) and not isinstance(member, bool) and 0 <= member < samples):
        raise ValueError(f"member {shown(member)} is not one of the study's 0 to {samples - 1}")
    if record["status"] not in STATUSES or record["status"] == "pending":
        raise ValueError(f"status {shown(record['status'])} unknown")
    if not all(isinstance(record[key], str) for key in ("message", "digest", "worker")):
        raise ValueError("message, digest and worker must be strings")
    numbers = [record["wall_seconds"], *(summary.values() if isinstance(summary, dict) else [])]
    if not isinstance(summary, dict) or not all(
        isinstance(value, float | int) and not isinstance(value, bool) for value in numbers
    ):
        raise ValueError("wall_seconds and the summary figures must be numbers")
    return MemberOutcome(
        member, record["status"], record["message"],
        {str(key): float(value) for key, value in summary.items()}, record["digest"],
        float(record["wall_seconds"]), record["worker"],
    )  # fmt: skip


class StudyFolder:
    """The folder of one study, held (locked) while it is open.

    Parameters
    ----------
    folder : Path
    """

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)
        self._hold: int | None = None
        self._journal: io.TextIOWrapper | None = None
        #: Journal lines skipped as damaged on opening: (line number, why).
        self.damaged: list[tuple[int, str]] = []

    @property
    def spec_path(self) -> Path:
        """``study.json``."""
        return self.folder / SPEC_FILE

    @property
    def journal_path(self) -> Path:
        """``members.jsonl``."""
        return self.folder / JOURNAL_FILE

    def open(self, spec: StudySpec, resume: bool) -> dict[int, MemberOutcome]:
        """Hold the folder and start or resume ``spec`` there; the members already finished.

        A folder holding another study, or this one without ``resume``, is a ConfigError
        before anything is written; so is a folder another study holds."""
        if resume and not self.spec_path.exists():
            raise ConfigError(f"--resume: no study in '{self.folder}' ({SPEC_FILE} missing)")
        prepare_output_dir(self.folder)
        self._hold = hold_folder(self.folder, "conslaw study")
        try:
            done = self._start(spec, resume)
            self._journal = open(self.journal_path, "a", encoding="utf-8")  # noqa: SIM115
        except BaseException:
            self.close()
            raise
        return done

    def _start(self, spec: StudySpec, resume: bool) -> dict[int, MemberOutcome]:
        if self.spec_path.exists() or self.spec_path.is_symlink():
            stored = StudySpec.from_json(self._read(self.spec_path), self.spec_path)
            if not resume:
                raise ConfigError(
                    f"output folder '{self.folder}' holds a study already: add --resume to "
                    "finish it, or choose another folder"
                )
            changed = stored.difference(spec)
            if changed is not None:
                raise ConfigError(
                    f"--resume: the study in '{self.folder}' was asked differently ({changed})"
                )
            return self._read_journal(spec.samples)
        if resume:
            raise ConfigError(f"--resume: no study in '{self.folder}' ({SPEC_FILE} missing)")
        if any(self.folder.iterdir()):
            raise ConfigError(
                f"output folder '{self.folder}' is not empty and holds no study: choose an "
                "empty or new folder"
            )
        atomic_write_bytes(self.spec_path, spec.to_json().encode())
        return {}

    def _read(self, path: Path) -> bytes:
        """The bytes of one of the study's files; a ConfigError naming it if it cannot be read
        (a folder in its place, no permission)."""
        try:
            return path.read_bytes()
        except OSError as error:
            raise ConfigError(
                f"cannot read '{path}' ({error.strerror or error}): restore it, or move the "
                "folder aside and run the study again"
            ) from None

    def _read_journal(self, samples: int) -> dict[int, MemberOutcome]:
        """The members of the journal. A last line cut short (a killed process) is cut off the
        file; any other line that is not one the study wrote (:func:`_outcome_from`) is
        skipped and kept in :attr:`damaged` as ``(line number, why)``: its member runs
        again."""
        if not (self.journal_path.exists() or self.journal_path.is_symlink()):
            return {}
        data = self._read(self.journal_path)
        complete = data[: data.rfind(b"\n") + 1]
        if len(complete) != len(data):
            with open(self.journal_path, "r+b") as stream:
                stream.truncate(len(complete))
        done: dict[int, MemberOutcome] = {}
        for number, line in enumerate(complete.splitlines(), 1):
            try:
                outcome = _outcome_from(line, samples)
            except (ValueError, TypeError, RecursionError, ArithmeticError) as error:
                self.damaged.append((number, str(error).splitlines()[0][:200]))
                continue
            done[outcome.index] = outcome
        return done

    def damage_note(self) -> str | None:
        """One line on the damaged journal lines skipped by :meth:`open`, or None."""
        if not self.damaged:
            return None
        number, why = self.damaged[0]
        more = f"; {len(self.damaged) - 1} more" if len(self.damaged) > 1 else ""
        return (
            f"{self.journal_path.name}: skipped {len(self.damaged)} damaged line(s) (line "
            f"{number}: {why}{more}); a member without an intact line runs again"
        )

    def record(self, outcome: MemberOutcome) -> None:
        """Keep a finished member: its maps first (atomically), then its journal line."""
        if self._journal is None:
            raise RuntimeError("the study folder is not open")
        if outcome.fields:
            self.save_fields(outcome.index, outcome.fields)
        self._journal.write(_outcome_line(outcome))
        self._journal.flush()

    def fields_path(self, index: int) -> Path:
        """The maps of member ``index``."""
        return self.folder / FIELDS_FOLDER / f"member-{index:06d}.npz"

    def save_fields(self, index: int, fields: dict[str, np.ndarray]) -> None:
        """Write a member's maps atomically."""
        path = self.fields_path(index)
        path.parent.mkdir(exist_ok=True)
        buffer = io.BytesIO()
        np.savez(buffer, allow_pickle=False, **fields)
        atomic_write_bytes(path, buffer.getvalue())

    def load_fields(self, index: int) -> dict[str, np.ndarray]:
        """A member's maps ({} if it kept none)."""
        path = self.fields_path(index)
        if not path.exists():
            return {}
        with np.load(path) as stored:
            return {name: np.array(stored[name]) for name in stored.files}

    def close(self) -> None:
        """Close the journal and let other studies use the folder."""
        if self._journal is not None:
            self._journal.close()
            self._journal = None
        if self._hold is not None:
            os.close(self._hold)
            self._hold = None
