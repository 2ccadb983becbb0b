"""The newcomer's tutorial (docs/tutorial-avalanche.md), executed as written: its files, its
commands, and the numbers it quotes."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from test_cli import cli

TUTORIAL = Path(__file__).resolve().parents[1] / "docs" / "tutorial-avalanche.md"


def test_the_tutorial_runs_as_written_and_prints_what_it_quotes(tmp_path: Path) -> None:
    text = TUTORIAL.read_text()
    files = dict(re.findall(r"```[a-z]+\n# file: (\S+)\n(.*?)```", text, re.DOTALL))
    assert set(files) == {"make_profile.py", "my-avalanche.toml", "read_results.py"}
    for name, body in files.items():
        (tmp_path / name).write_text(body)

    def python(script: str) -> str:
        process = subprocess.run(
            [sys.executable, script], cwd=tmp_path, capture_output=True, text=True, timeout=120
        )
        assert process.returncode == 0, process.stderr
        return process.stdout

    python("make_profile.py")
    assert "    conslaw run my-avalanche.toml --out out/my-avalanche\n" in text
    run = cli("run", "my-avalanche.toml", "--out", "out/my-avalanche", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    for figure in ("profiles.png", "chute.png"):
        assert (tmp_path / "out" / "my-avalanche" / figure).stat().st_size > 0
    quoted = re.search(
        r"    python read_results.py\n\nprints\n\n```text\n(.*?)```", text, re.DOTALL
    )
    assert quoted is not None
    assert python("read_results.py") == quoted.group(1)

    # Section 5: less bed friction, the front further down.
    other = cli(
        "run", "my-avalanche.toml", "--set", "parameters.delta=24", "--no-plot", "--out",
        "out/delta24", cwd=tmp_path,
    )  # fmt: skip
    assert other.returncode == 0, other.stderr
    (tmp_path / "read_results.py").write_text(
        files["read_results.py"].replace("out/my-avalanche", "out/delta24")
    )
    assert "to 78.1\n" in python("read_results.py")
    assert "front moves from x = 72.8 to 78.1" in text
