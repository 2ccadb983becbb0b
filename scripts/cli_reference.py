"""Print the command-line reference (docs/cli.md) from the argument parser in conslaw.cli.

python scripts/cli_reference.py > docs/cli.md
"""

from __future__ import annotations

import argparse

from conslaw.cli import build_parser

#: Width of the help text (fixed, so the page does not depend on the terminal).
WIDTH = 90

#: A line of a run written to a log (``conslaw run sh2d-runout > log``).
EXAMPLE_LINE = (
    "conslaw: t=15.114 of 30 (50.4%), 354 steps, dt=0.0419, 3434 moving cells, "
    "10.0 s elapsed, about 9.8 s left"
)
#: The section on progress output (conslaw.progress), after the introduction.
PROGRESS = """\
## Progress

`conslaw run` shows how far it is. On a terminal it redraws one line, a bar with the model
time, the steps and an estimate of the time left:

```text
[################..............] t=16.98 steps=398, about 3.4 s left
```

When its output is not a terminal (`conslaw run SCENE > log 2>&1`, `nohup`, a batch
scheduler) it writes a plain line every 10 s of wall time instead, flushed at once so that
`tail -f log` shows it:

```text
EXAMPLE_LINE
```

that is the model time of `t_end` (and percent), the steps, the mean step size `dt` since the
previous report, in 2D runs of a model with a momentum the cells whose momentum is not 0, the
wall time since the first step (a compile before it is not counted), and the time left at the
rate the model time has advanced so far (`estimating time left` for the first 2 s and the first
1 % of the run). `conslaw ensemble` and `conslaw calibrate` write lines of the same form about
their members (`conslaw: study: 5 of 10 members done, 1 did not finish, 12.0 s elapsed, about
12.0 s left`; a calibration per stage), every 10 s without a terminal and every 5 s on one, and
the study's last member always. The environment variable `CONSLAW_PROGRESS_SECONDS` sets the
10 s (a number >= 0; 0 writes a line at every report, as the tests do).

`--quiet` (`-q`, before or after the command) leaves the progress out: no bar, no progress
lines, no notice of a kernel compile, and in a study or a calibration none of its `conslaw: ...`
lines (resuming, stopping, each stage's result). Errors (stderr) and the summary at the end (what
ran, the errors against an exact solution, the files written) are printed as without it, so a
script can still read them; `conslaw warm --quiet` prints one line at the end instead of a line
per kernel family.
"""


def _fixed_width(parser: argparse.ArgumentParser) -> None:
    parser.formatter_class = lambda prog: argparse.HelpFormatter(prog, width=WIDTH)


def render() -> str:
    """The markdown page: ``conslaw --help`` and the help of every subcommand."""
    parser = build_parser()
    _fixed_width(parser)
    lines = [
        "# Command-line reference",
        "",
        "Every command and option of `conslaw`, as `conslaw COMMAND --help` prints them.",
        "Errors in the input are one line on stderr and exit code 2; an interrupted run (Ctrl-C,",
        "SIGTERM) says where it stopped and exits with 128 + the signal number.",
        "",
        "This page is generated from `conslaw.cli.build_parser` by "
        "`python scripts/cli_reference.py > docs/cli.md`.",
        "",
        PROGRESS.replace("EXAMPLE_LINE", EXAMPLE_LINE).rstrip(),
        "",
        "## `conslaw`",
        "",
        "```text",
        parser.format_help().rstrip(),
        "```",
    ]
    subcommands = next(
        action for action in parser._actions if isinstance(action, argparse._SubParsersAction)
    )
    for name, sub in subcommands.choices.items():
        _fixed_width(sub)
        lines += ["", f"## `conslaw {name}`", "", "```text", sub.format_help().rstrip(), "```"]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
