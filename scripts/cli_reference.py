"""Print the command-line reference (docs/cli.md) from the argument parser in conslaw.cli.

python scripts/cli_reference.py > docs/cli.md
"""

from __future__ import annotations

import argparse

from conslaw.cli import build_parser

#: Width of the help text (fixed, so the page does not depend on the terminal).
WIDTH = 90


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
