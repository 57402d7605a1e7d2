"""What the docs, the ``--help`` texts and the messages tell a user to type or follow exists.

Every ``xrdf COMMAND … --option`` written in README.md, docs/*.md or the package's sources
(help texts, diagnostics, rule docs) names an option of that command, and every ``--option``
named anywhere there is an option of some command or of a benchmark script. Every option of
every command says what it does. The usage block at the top of a command's page names
exactly its options. Every link of the docs reaches a file and heading."""

from __future__ import annotations

import re
from collections.abc import Iterator
from functools import cache
from pathlib import Path
from typing import Any

import typer.main

from tests.paths import REPO
from xrdf_tools.cli import app

#: ``xrdf CMD`` (``xrdf export SUB``) and the rest of its command line in one piece of text: up
#: to the end of a code span, a quote, a pipe, ``;``, ``&`` or the end of the line.
_COMMAND = re.compile(r"\bxrdf ((?:export )?[a-z]+)\b([^`|;&\n'\"]*)")
_OPTION = re.compile(r"(?<![\w/.-])(--[a-z][a-z0-9-]*|-[a-zA-Z])(?![\w-])")
_ARGPARSE = re.compile(r"add_argument\(\s*\"(--[a-z][a-z0-9-]*)\"")


def _walk(command: Any, path: tuple[str, ...]) -> Iterator[tuple[tuple[str, ...], Any]]:
    if hasattr(command, "commands"):
        for name, sub in command.commands.items():
            yield from _walk(sub, (*path, name))
    else:
        yield path, command


@cache
def _commands() -> dict[tuple[str, ...], Any]:
    return dict(_walk(typer.main.get_command(app), ()))


@cache
def _options() -> dict[tuple[str, ...], frozenset[str]]:
    return {
        path: frozenset(
            {"--help"}
            | {o for p in cmd.params for o in (*p.opts, *p.secondary_opts) if o.startswith("-")}
        )
        for path, cmd in _commands().items()
    }


def _sources() -> list[Path]:
    docs = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
    return docs + sorted((REPO / "xrdf_tools").rglob("*.py"))


def _unknown_options_of_commands(text: str) -> Iterator[tuple[int, str, str]]:
    """``(line, command, option)`` for each option a written ``xrdf`` command line does not
    have (shell line continuations joined)."""
    options = _options()
    joined = re.sub(r"\\\n\s*", " ", text)
    for m in _COMMAND.finditer(joined):
        words = tuple(m.group(1).split())
        if words not in options:
            continue  # "xrdf export" alone, or prose such as "xrdf files"
        for option in _OPTION.findall(m.group(2)):
            if option not in options[words]:
                yield joined[: m.start()].count("\n") + 1, " ".join(words), option


def test_the_checker_finds_an_option_a_command_lacks() -> None:
    text = "run `xrdf convert robot.urdf --to 2.0` or\nxrdf lint a.xrdf \\\n    --urdf u.urdf -z"
    assert list(_unknown_options_of_commands(text)) == [
        (1, "convert", "--to"),
        (2, "lint", "-z"),
    ]


def test_every_written_command_line_uses_options_the_command_has() -> None:
    found = [
        f"{path.relative_to(REPO)}:{n}: xrdf {command} has no {option}"
        for path in _sources()
        for n, command, option in _unknown_options_of_commands(path.read_text(encoding="utf-8"))
    ]
    assert found == []


_SYNOPSIS = re.compile(r"^```\n(xrdf [a-z]+ .*?)^```", re.S | re.M)


def _synopsis_lines(block: str) -> Iterator[tuple[tuple[str, ...], str]]:
    """``(command words, its line with the indented lines below it)`` of a synopsis block."""
    for m in re.finditer(r"^xrdf ((?:export )?[a-z]+)\b(.*(?:\n[ \t]+.*)*)", block, re.M):
        yield tuple(m.group(1).split()), m.group(2)


def _synopsis_faults(block: str) -> Iterator[str]:
    """What a synopsis gets wrong: an option its command lacks, or an option of the command it
    leaves out (one of its spellings is enough)."""
    for words, line in _synopsis_lines(block):
        named = set(_OPTION.findall(line))
        command = " ".join(words)
        for option in sorted(named - _options()[words]):
            yield f"xrdf {command} has no {option}"
        for param in _commands()[words].params:
            spellings = {*param.opts, *param.secondary_opts}
            if param.param_type_name == "option" and not spellings & (named | {"--help"}):
                yield f"xrdf {command}: {param.opts[0]} left out"


def test_the_synopsis_checker_reads_continuation_lines() -> None:
    block = "xrdf diff A B [--tolerance T] [-f text|json]\n    [--urdf U] [--bogus]\n"
    assert sorted(_synopsis_faults(block)) == [
        "xrdf diff has no --bogus",
        "xrdf diff: --package-path left out",
        "xrdf diff: --xacro-arg left out",
        "xrdf diff: -q left out",
        "xrdf diff: -v left out",
    ]


def test_every_synopsis_names_every_option_of_its_command_and_no_other() -> None:
    """The usage block at the top of a command's page (``xrdf report ROBOT.xrdf --urdf …
    [--samples N] …``, continued on indented lines) lists exactly the command's options."""
    faults = [
        f"{doc.name}: {fault}"
        for doc in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
        for block in _SYNOPSIS.findall(doc.read_text(encoding="utf-8"))
        if "[" in block  # the README's list of commands is no synopsis
        for fault in _synopsis_faults(block)
    ]
    assert faults == []


def test_every_option_named_in_the_docs_and_messages_exists() -> None:
    known = set().union(*_options().values())
    known |= {o for p in typer.main.get_command(app).params for o in p.opts}
    for script in (REPO / "benchmarks").glob("*.py"):
        known |= set(_ARGPARSE.findall(script.read_text(encoding="utf-8")))
    unknown = []
    for path in _sources():
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for option in re.findall(r"(?<![\w/.-])(--[a-z][a-z0-9-]*)", line):
                if option not in known:
                    unknown.append(f"{path.relative_to(REPO)}:{n}: {option}")
    assert unknown == []


def test_every_option_says_what_it_does() -> None:
    silent = [
        f"xrdf {' '.join(path)} {param.opts[0]}"
        for path, cmd in _commands().items()
        for param in cmd.params
        if param.param_type_name == "option" and not (param.help or "").strip()
    ]
    assert silent == []


def test_convert_help_gives_the_default_limits_convert_uses() -> None:
    from xrdf_tools.convert.core import DEFAULT_ACCELERATION, DEFAULT_JERK

    helps = {p.name: p.help for p in _commands()[("convert",)].params}
    assert f"Default: {DEFAULT_ACCELERATION:g}," in helps["acceleration"]
    assert f"Default: {DEFAULT_JERK:g}," in helps["jerk"]


_FENCED = re.compile(r"^```.*?^```", re.S | re.M)


def _headings(doc: Path) -> set[str]:
    """The anchors of ``doc``'s headings, spelled as the Markdown renderers make them."""
    text = _FENCED.sub("", doc.read_text(encoding="utf-8"))
    return {
        re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
        for m in re.finditer(r"^#+\s+(.*)$", text, re.M)
    }


def test_every_link_in_the_docs_points_at_a_file_and_heading_that_exist() -> None:
    broken = []
    for doc in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        text = _FENCED.sub("", doc.read_text(encoding="utf-8"))
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):  # a web address
                continue
            path, _, anchor = target.partition("#")
            linked = doc.parent / path if path else doc
            if not linked.exists():
                broken.append(f"{doc.name}: {target}: no such file")
            elif anchor and linked.suffix == ".md" and anchor not in _headings(linked):
                broken.append(f"{doc.name}: {target}: no such heading")
    assert broken == []


def _params_named(opt: str) -> dict[str, Any]:
    """``{command: click parameter}`` of the option spelled ``opt`` in every command."""
    return {
        " ".join(path): p for path, cmd in _commands().items() for p in cmd.params if opt in p.opts
    }


def test_an_option_several_commands_share_reads_the_same_in_each() -> None:
    from xrdf_tools.cli.commands import options

    targets = _params_named("--target")
    assert set(targets) == {"convert", "lint", "export xrdf"}
    assert all(p.help.startswith(options.target("").help.strip()) for p in targets.values())
    versions = _params_named("--format-version")
    assert set(versions) == {"convert", "export xrdf"}
    assert {p.metavar for p in (*targets.values(), *versions.values())} == {
        "<curobo|cumotion|isaac-sim>",
        "<1.0|2.0>",
    }
    seeds = _params_named("--seed")
    assert set(seeds) == {"convert", "report", "viz", "spheres", "edit"}
    assert all(p.type.min == 0 and "same seed" in p.help for p in seeds.values())
    stdout_outputs = {k: p for k, p in _params_named("-o").items() if k != "edit"}
    assert len(stdout_outputs) == 7  # convert, report, spheres, expand, export curobo|srdf|xrdf
    assert all("to stdout" in p.help and "atomically" in p.help for p in stdout_outputs.values())
    assert all("-f" in p.opts for p in _params_named("--format").values())
    configs = _params_named("--configs")
    assert set(configs) == {"report", "viz", "edit"}
    assert all(".json/.yaml" in p.help for p in configs.values())


def test_every_command_help_shows_an_example() -> None:
    missing = [
        " ".join(path)
        for path, cmd in _commands().items()
        if "Examples:" not in (cmd.help or "") or f"xrdf {' '.join(path)} " not in cmd.help
    ]
    assert missing == []


def test_every_docs_page_is_linked_from_the_readme_or_the_docs_index() -> None:
    linked = {
        (doc.parent / target.partition("#")[0]).resolve()
        for doc in (REPO / "README.md", REPO / "docs" / "index.md")
        for target in re.findall(r"\]\(([^)\s#]+)", doc.read_text(encoding="utf-8"))
    }
    pages = {p.resolve() for p in (REPO / "docs").glob("*.md")} - {REPO / "docs" / "index.md"}
    assert sorted(p.name for p in pages - linked) == []
