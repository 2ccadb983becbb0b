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

import io
import json
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from conslaw.ensemble.member import MemberOutcome
from conslaw.errors import ConfigError
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
    def from_json(cls, text: str, where: Path) -> StudySpec:
        """Read ``study.json``; a ConfigError naming the file if it is not one."""
        try:
            return cls(**json.loads(text))
        except (ValueError, TypeError) as error:
            raise ConfigError(f"'{where}' is not a conslaw study description ({error})") from None

    def difference(self, other: StudySpec) -> str | None:
        """The first field in which ``other`` asks for another study, as text, or None."""
        mine, theirs = asdict(self), asdict(other)
        for key in mine:
            if key != "extra" and mine[key] != theirs[key]:
                return f"{key}: {mine[key]!r} there, {theirs[key]!r} now"
        return None


def _outcome_line(outcome: MemberOutcome) -> str:
    record = {
        "member": outcome.index,
        "status": outcome.status,
        "message": outcome.message,
        "digest": outcome.digest,
        "wall_seconds": outcome.wall_seconds,
        "worker": outcome.worker,
        "summary": outcome.summary,
    }
    return json.dumps(record, allow_nan=True) + "\n"


def _outcome_from(record: dict[str, Any]) -> MemberOutcome:
    summary = {key: float(value) for key, value in record["summary"].items()}
    return MemberOutcome(
        int(record["member"]), str(record["status"]), str(record["message"]),
        summary, str(record["digest"]), float(record["wall_seconds"]), str(record["worker"]),
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
        if self.spec_path.exists():
            stored = StudySpec.from_json(self.spec_path.read_text(), self.spec_path)
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
            return self._read_journal()
        if resume:
            raise ConfigError(f"--resume: no study in '{self.folder}' ({SPEC_FILE} missing)")
        if any(self.folder.iterdir()):
            raise ConfigError(
                f"output folder '{self.folder}' is not empty and holds no study: choose an "
                "empty or new folder"
            )
        atomic_write_bytes(self.spec_path, spec.to_json().encode())
        return {}

    def _read_journal(self) -> dict[int, MemberOutcome]:
        """The members of the journal; a last line cut short is cut off the file."""
        if not self.journal_path.exists():
            return {}
        data = self.journal_path.read_bytes()
        complete = data[: data.rfind(b"\n") + 1]
        if len(complete) != len(data):
            with open(self.journal_path, "r+b") as stream:
                stream.truncate(len(complete))
        done: dict[int, MemberOutcome] = {}
        for number, line in enumerate(complete.decode("utf-8").splitlines(), 1):
            try:
                outcome = _outcome_from(json.loads(line))
            except (ValueError, KeyError, TypeError):
                raise ConfigError(
                    f"'{self.journal_path}' line {number} is damaged: move the folder aside "
                    "and run the study again"
                ) from None
            done[outcome.index] = outcome
        return done

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
