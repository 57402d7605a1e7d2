"""The ``xrdf`` app built with only the command a command line runs (what the entry point
does) reads, helps and fails exactly as the app with every command."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from tests.paths import SEED_XRDF, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli.commands.app import COMMANDS, GROUPS, app_for, build_app, full_app

NAMES = [name for name, *_ in (*COMMANDS, *GROUPS)]


def _lines(name: str) -> list[list[str]]:
    return [[name, "--help"], [name], [name, "--bogus"], [name, "--version"]]


@pytest.mark.parametrize("name", NAMES)
def test_one_command_app_helps_and_fails_as_the_whole_app(name: str, runner: CliRunner) -> None:
    one = build_app([name])
    for words in _lines(name):
        a = runner.invoke(full_app(), words)
        b = runner.invoke(one, words)
        assert (b.exit_code, b.stdout, b.stderr) == (a.exit_code, a.stdout, a.stderr), words


def test_one_command_app_runs_the_command_as_the_whole_app(runner: CliRunner) -> None:
    for words in (
        ["diff", str(UR10E_XRDF), str(SEED_XRDF)],
        ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF)],
        ["inspect", str(UR10E_URDF), "--format", "json"],
    ):
        a = runner.invoke(full_app(), words)
        b = runner.invoke(app_for(words), words)
        assert (b.exit_code, b.stdout, b.stderr) == (a.exit_code, a.stdout, a.stderr), words


def test_anything_but_a_command_gets_the_whole_app() -> None:
    assert app_for([]) is full_app()
    assert app_for(["--help"]) is full_app()
    assert app_for(["reprot", "a.xrdf"]) is full_app()  # typer says which commands exist
    one = app_for(["report", "a.xrdf"])
    assert [c.name for c in one.registered_commands] == ["report"] and not one.registered_groups


def test_the_whole_app_lists_every_command_in_order(runner: CliRunner) -> None:
    r = runner.invoke(full_app(), ["--help"])
    listed = [
        line.split()[0]
        for line in r.stdout.split("Commands:")[1].splitlines()
        if line.startswith("  ")
    ]
    assert listed == [name for name, _ in COMMANDS] + [name for name, *_ in GROUPS]


@pytest.mark.parametrize("words", [["--help"], ["export", "--help"]])
def test_command_lists_show_each_summary_whole(runner: CliRunner, words: list[str]) -> None:
    """`xrdf --help` cut export's summary to 'or an XRDF for a...', and `xrdf export --help`
    all three of its commands' ('lists in c-space...', "MoveIt SRDF's..."): on an 80-column
    terminal (the width click assumes off one) each command's summary is shown whole."""
    r = runner.invoke(full_app(), words, terminal_width=80)
    assert r.exit_code == 0
    listed = [x for x in r.stdout.split("Commands:")[1].splitlines() if x.startswith("  ")]
    assert listed and not any(x.rstrip().endswith("...") for x in listed), listed
