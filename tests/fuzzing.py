"""A seeded mutator over the real fixtures and a harness that runs the ``xrdf`` CLI on the result.

Used by ``tests/cli/test_fuzz_cli.py`` (a bounded run in CI) and ``benchmarks/fuzz_cli.py`` (10,000+
runs locally). A :class:`Case` is fully determined by its number and the run seed: the same
number always builds the same inputs, so any failure is reproducible with
``python benchmarks/fuzz_cli.py --case N``.

Each case copies the seed inputs into a fresh directory, damages one of them (text mutations:
tokens, values, lines, cuts, hostile YAML/XML snippets, bad bytes; file mutations: a directory,
a FIFO or a link to ``/dev/zero`` in its place) and runs one command on them. :func:`run_case`
checks what the README promises: exit code 0, 1 or 2, no traceback, no ``internal-error``
finding, an error about the damaged file carries its line (:func:`unlocated_errors`), and every
input file unchanged.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import io
import os
import random
import re
import shutil
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
FIXTURES = REPO / "fixtures"

#: Seed files per kind (the first is the one commands use when another kind is mutated).
SEEDS: dict[str, list[Path]] = {
    "xrdf": [
        FIXTURES / "ur10e" / "ur10e.xrdf",
        FIXTURES / "seed" / "ur10e_seed.xrdf",
        FIXTURES / "panda" / "panda.xrdf",
        *sorted((FIXTURES / "lint").glob("*/pass*.xrdf")),
    ],
    "urdf": [FIXTURES / "ur10e" / "ur10e.urdf"],
    "mimic_urdf": [FIXTURES / "urdf" / "three_link_mimic.urdf"],
    "mimic_xrdf": [FIXTURES / "fuzz" / "three_link_mimic.xrdf"],
    "srdf": [FIXTURES / "fuzz" / "ur10e.srdf"],
    "limits": [FIXTURES / "fuzz" / "joint_limits.yaml"],
    "config": [FIXTURES / "fuzz" / "xrdf-lint.yaml"],
    "configs": [FIXTURES / "fuzz" / "configs.csv", FIXTURES / "fuzz" / "configs.yaml"],
    "xacro": [FIXTURES / "fuzz" / "arm.urdf.xacro"],
    "curobo": [
        FIXTURES / "curobo_classic" / "ur10e_classic.yml",
        FIXTURES / "curobo_classic" / "ur10e_inline.yml",
        FIXTURES / "curobo_classic" / "ur10e_lula.yaml",
        FIXTURES / "curobo_classic" / "ur10e_real_patterns.yml",
        FIXTURES / "curobo_classic" / "ur10e_floating_base.yml",
    ],
    "spheres": [FIXTURES / "curobo_classic" / "spheres" / "ur10e.yml"],
    "mesh_urdf": [FIXTURES / "fuzz" / "visual_mesh.urdf"],
    "mesh": [FIXTURES / "fuzz" / "arm_visual.dae"],
}

#: Where each kind is placed in the work directory (``{ext}`` keeps the seed's suffix).
LAYOUT: dict[str, str] = {
    "xrdf": "robot.xrdf",
    "urdf": "ur10e.urdf",
    "mimic_urdf": "mimic.urdf",
    "mimic_xrdf": "mimic.xrdf",
    "srdf": "ur10e.srdf",
    "limits": "joint_limits.yaml",
    "config": ".xrdf-lint.yaml",
    "configs": "configs{ext}",
    "xacro": "arm.urdf.xacro",
    "curobo": "curobo/robot{ext}",
    "spheres": "curobo/spheres/ur10e.yml",
    "mesh_urdf": "visual_mesh.urdf",
    "mesh": "meshes/arm_visual.dae",
}


@dataclass(frozen=True)
class Scenario:
    """One command line; ``{kind}`` fields are input paths, ``@name`` output paths."""

    name: str
    args: tuple[str, ...]
    mutable: tuple[str, ...]  # kinds whose damage this scenario is meant to exercise
    slow: bool = False  # seconds per run: left out of the CI subset


SCENARIOS: tuple[Scenario, ...] = (
    Scenario("lint", ("lint", "{xrdf}"), ("xrdf", "config")),
    Scenario("lint-urdf", ("lint", "{xrdf}", "--urdf", "{urdf}"), ("xrdf", "urdf")),
    Scenario("lint-config", ("lint", "{xrdf}", "--config", "{config}"), ("config",)),
    Scenario("diff", ("diff", "{xrdf}", "{other}"), ("xrdf",)),
    Scenario("diff-urdf", ("diff", "{xrdf}", "{other}", "--urdf", "{urdf}"), ("urdf",)),
    Scenario(
        "convert-srdf",
        ("convert", "{urdf}", "--srdf", "{srdf}", "--joint-limits", "{limits}", "-o", "@out"),
        ("srdf", "limits", "urdf"),
    ),
    Scenario(
        "convert-curobo", ("convert", "{urdf}", "--curobo", "{curobo}"), ("curobo", "spheres")
    ),
    Scenario("convert-xacro", ("convert", "{xacro}"), ("xacro",)),
    Scenario("expand-xacro", ("expand", "{xacro}", "-o", "@out"), ("xacro",)),
    Scenario("inspect", ("inspect", "{urdf}", "--srdf", "{srdf}"), ("urdf", "srdf")),
    Scenario("inspect-xacro", ("inspect", "{xacro}", "--format", "json"), ("xacro",)),
    Scenario("convert-mimic", ("convert", "{mimic_urdf}"), ("mimic_urdf",)),
    Scenario("export-curobo", ("export", "curobo", "{xrdf}", "--urdf", "{urdf}"), ("xrdf", "urdf")),
    Scenario(
        "export-srdf", ("export", "srdf", "{xrdf}", "--merge", "{srdf}", "-o", "@out"), ("srdf",)
    ),
    Scenario(
        "report",
        ("report", "{xrdf}", "--urdf", "{urdf}", "-n", "64", "-o", "@out", "--write-mask", "@mask"),
        ("xrdf", "urdf"),
    ),
    Scenario(
        "report-certify",
        (
            "report",
            "{xrdf}",
            "--urdf",
            "{urdf}",
            "-n",
            "64",
            "--certify",
            "--certify-boxes",
            "2000",
            "-f",
            "json",
        ),
        ("xrdf", "urdf"),
    ),
    Scenario(
        "report-configs",
        ("report", "{xrdf}", "--urdf", "{urdf}", "--configs", "{configs}", "-f", "json"),
        ("configs",),
    ),
    Scenario(
        "viz",
        ("viz", "{xrdf}", "--urdf", "{urdf}", "--mcap", "@out", "--meshes", "none", "-n", "2"),
        ("xrdf", "urdf"),
    ),
    Scenario(
        "viz-mimic",
        ("viz", "{mimic_xrdf}", "--urdf", "{mimic_urdf}", "--png", "@out", "-n", "2"),
        ("mimic_urdf", "mimic_xrdf"),
    ),
    Scenario(
        "report-mimic",
        ("report", "{mimic_xrdf}", "--urdf", "{mimic_urdf}", "-n", "256", "--plot", "@out"),
        ("mimic_urdf", "mimic_xrdf"),
    ),
    Scenario(
        "spheres",
        (
            "spheres",
            "{mimic_urdf}",
            "--per-link",
            "2",
            "--links",
            "finger,link3",  # two small links: seconds, not tens of seconds, per run
            "--xrdf",
            "{mimic_xrdf}",
            "-o",
            "@out",
        ),
        ("mimic_urdf", "mimic_xrdf"),
        slow=True,
    ),
    Scenario(
        "spheres-morphit",
        (
            "spheres",
            "{mimic_urdf}",
            "--per-link",
            "2",
            "--links",
            "finger,link3",
            "--method",
            "morphit",
            "-o",
            "@out",
        ),
        ("mimic_urdf",),
        slow=True,
    ),
    Scenario(
        "spheres-visual",  # the visual check: the COLLADA reader, then trimesh's
        ("spheres", "{mesh_urdf}", "--per-link", "1", "--visual-check", "all", "-o", "@out"),
        ("mesh",),
        slow=True,
    ),
)

_YAML_VALUES = (
    "5",
    "-1",
    "0",
    "1e308",
    "-1e308",
    ".inf",
    ".nan",
    "null",
    "~",
    "true",
    "''",
    '"x\\ny"',
    "[]",
    "{}",
    "[1, [2]]",
    "{a: 1}",
    "[a, b]",
    "{center: [0, 0], radius: -1}",
    "!!binary AAAA",
    "&anchor 1",
    "*nope",
    "99999999999999999999999",
    "0x1F",
    "1_000",
    "'\\u0000'",
)
_YAML_SNIPPETS = (
    "a: &a [*a]\n",
    "? {a: 1}\n: 2\n",
    "? [1, 2]\n: x\n",
    "x: \x01\n",
    "x: \ufffe\n",
    "x: a\x85b\n",
    "\t- tab\n",
    "---\nsecond: document\n",
    "%YAML 1.1\n",
    "x: !!python/object/apply:os.system ['true']\n",
    "<<: *missing\n",
    "deep: " + "[" * 150 + "]" * 150 + "\n",
    "deep2: " + "{a: " * 120 + "1" + "}" * 120 + "\n",
    "l0: &l0 [x]\n"
    + "".join(f"l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]\n" for i in range(1, 9)),
    "k: " + "x" * 20000 + "\n",
)
_XML_VALUES = (
    "",
    "1 2",
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1",
    "0 0 0",
    "1 2 3 4",
    "a b c",
    "base_link",
    "tool0",
    "joint1",
    "shoulder_pan_joint",
    "&amp;",
    "\u00e9",
    "0" * 400,
    "1e-320",
)
_XML_SNIPPETS = (
    '<!DOCTYPE robot [<!ENTITY e SYSTEM "file:///etc/passwd">]>',
    "&e;",
    '<!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
    '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;">]>',
    "<link name='base_link'/>",
    "<joint name='loop' type='fixed'><parent link='tool0'/><child link='base_link'/></joint>",
    "<joint name='self' type='fixed'><parent link='tool0'/><child link='tool0'/></joint>",
    "<link name='x'><visual><geometry><box size='1 2'/></geometry></visual></link>",
    "<link name='y'><collision><geometry><sphere radius='-1'/></geometry></collision></link>",
    "<group name='g1'><group name='g2'/></group><group name='g2'><group name='g1'/></group>",
    "<group name='big'><chain base_link='tool0' tip_link='base_link'/></group>",
    "<xacro:macro name='m'><xacro:m/></xacro:macro><xacro:m/>",
    "<a>" * 300 + "</a>" * 300,
    "<![CDATA[",
    "<?xml version='1.0'?>",
    "\x00",
)
_CSV_VALUES = ("nan", "inf", "1e308", "x", "", ",", "0 0 0 0 0 0 0 0", "#")
#: Numbers at and past the bounds of every reader, and spellings YAML 1.1 reads differently.
_EXTREME_NUMBERS = (
    "1e308",
    "-1e308",
    "1e13",
    "1e7",
    "9223372036854775808",
    "9" * 400,
    "5e-324",
    "nan",
    "017",
    "0o17",
    "1:30",
    "1e-3",
    "1.0e3",
    "yes",
    "off",
)
#: -n values past the sample ceiling, or not a count at all.
_HUGE_COUNTS = ("99999999999999999999999", "10000000001", "0", "-5")
_NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w.])")

_TOKEN = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?|[A-Za-z_][\w-]*")
_YAML_VALUE = re.compile(r"(?m)^(\s*(?:- )?[\w.-]+:)[ \t]*(.*)$")
_XML_ATTR = re.compile(r'(\w+)=(["\'])([^"\']*)\2')


@dataclass
class Case:
    """One fuzz run: a scenario, the kind damaged, the damage done (for the report)."""

    number: int
    scenario: Scenario
    kind: str
    seed_file: Path
    ops: list[str] = field(default_factory=list)
    text: bytes | None = None  # the damaged content (None: a file-type mutation)
    special: str | None = None  # "directory" | "fifo" | "devzero"
    count: str | None = None  # a -n/--samples value put in place of the scenario's
    stream: str | None = None  # standard output "full" | "broken" | "none" (closed)


def _suffix(path: Path) -> str:
    return "".join(path.suffixes[-1:])


def _fmt(kind: str) -> str:
    if kind in ("urdf", "mimic_urdf", "srdf", "xacro", "mesh_urdf", "mesh"):
        return "xml"
    if kind == "configs":
        return "csv"
    return "yaml"


def _line_starts(text: str) -> list[int]:
    return [0, *(m.end() for m in re.finditer("\n", text))]


_OPS = ("token", "value", "line", "cut", "snippet", "dup")
_OP_WEIGHTS = (3, 5, 2, 1, 2, 1)  # mostly damage that still parses, to reach the readers


def _mutate_text(text: str, fmt: str, rng: random.Random) -> tuple[str, str]:
    """One text mutation; returns the new text and a short label."""
    op = rng.choices(_OPS, _OP_WEIGHTS)[0]
    if op == "token":
        toks = list(_TOKEN.finditer(text))
        if toks:
            m = rng.choice(toks)
            pool = {"xml": _XML_VALUES, "csv": _CSV_VALUES}.get(fmt, _YAML_VALUES)
            new = rng.choice([*pool, rng.choice(toks).group()])
            return text[: m.start()] + new + text[m.end() :], f"token {m.group()!r}->{new!r}"
    if op == "value" and fmt == "yaml":
        vals = list(_YAML_VALUE.finditer(text))
        if vals:
            m = rng.choice(vals)
            new = rng.choice(_YAML_VALUES)
            return text[: m.start(2)] + new + text[m.end(2) :], f"value {m.group(1).strip()}={new}"
    if op == "value" and fmt == "xml":
        attrs = list(_XML_ATTR.finditer(text))
        if attrs:
            m = rng.choice(attrs)
            new = rng.choice(_XML_VALUES)
            return text[: m.start(3)] + new + text[m.end(3) :], f"attr {m.group(1)}={new!r}"
    starts = _line_starts(text)
    if op == "line" and len(starts) > 2:
        i = rng.randrange(len(starts) - 1)
        line = text[starts[i] : starts[i + 1]]
        how = rng.choice(("delete", "duplicate", "indent", "dedent"))
        new = {"delete": "", "duplicate": line + line, "indent": "  " + line}.get(
            how, line.lstrip()
        )
        return text[: starts[i]] + new + text[starts[i + 1] :], f"line {i + 1} {how}"
    if op == "dup" and len(text) > 10:
        a = rng.randrange(len(text))
        b = min(len(text), a + rng.randrange(1, 400))
        at = rng.choice(starts)
        return text[:at] + text[a:b] + text[at:], f"copy [{a}:{b}] to {at}"
    if op == "cut" and text:
        at = rng.randrange(len(text))
        return text[:at], f"cut at {at}"
    pool = {"xml": _XML_SNIPPETS, "csv": _CSV_VALUES}.get(fmt, _YAML_SNIPPETS)
    snippet = rng.choice(pool)
    at = rng.choice(starts)
    if fmt == "xml" and not snippet.startswith("<!DOCTYPE"):
        closing = text.rfind("</")
        at = closing if closing > 0 and rng.random() < 0.7 else at
    elif fmt == "xml":
        at = 0
    return text[:at] + snippet + ("\n" if fmt == "csv" else "") + text[at:], f"snippet@{at}"


def _mutate_bytes(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    at = rng.randrange(len(data) + 1)
    junk = rng.choice((b"\xff", b"\xc3\x28", b"\x00", b"\xed\xa0\x80", b"\xef\xbb\xbf", b"\x1b[2J"))
    return data[:at] + junk + data[at:], f"bytes {junk!r}@{at}"


def make_case(number: int, run_seed: int = 0, *, slow: bool = True) -> Case:
    """The case ``number`` of run ``run_seed`` (deterministic); ``slow``: include the slow
    scenarios."""
    rng = random.Random(f"{run_seed}:{number}")
    scenario = rng.choice([s for s in SCENARIOS if slow or not s.slow])
    kind = rng.choice(scenario.mutable)
    seed_file = rng.choice(SEEDS[kind])
    case = Case(number, scenario, kind, seed_file)
    roll = rng.random()
    if roll < 0.02 and os.name == "posix":
        case.special = rng.choice(("directory", "fifo", "devzero"))
        case.ops.append(f"replace with {case.special}")
        return case
    data = seed_file.read_bytes()
    if roll < 0.07:
        data, label = _mutate_bytes(data, rng)
        case.ops.append(label)
    else:
        text = data.decode("utf-8")
        for _ in range(rng.choice((1, 1, 1, 2, 3))):
            text, label = _mutate_text(text, _fmt(kind), rng)
            case.ops.append(label)
        data = text.encode("utf-8", "surrogatepass")
    case.text = data
    _harden(case, random.Random(f"{run_seed}:{number}:limits"))
    return case


def _harden(case: Case, rng: random.Random) -> None:
    """Damage of its own random stream (the cases without it are unchanged): a number pushed
    to an extreme, a huge ``-n``, or a faulty standard output."""
    roll = rng.random()
    if roll < 0.15 and case.text is not None:
        try:
            text = case.text.decode("utf-8", "surrogatepass")
        except UnicodeDecodeError:  # damaged bytes: a case of their own already
            return
        numbers = list(_NUMBER.finditer(text))
        if numbers:
            m = rng.choice(numbers)
            new = rng.choice(_EXTREME_NUMBERS)
            case.text = (text[: m.start()] + new + text[m.end() :]).encode("utf-8", "surrogatepass")
            case.ops.append(f"extreme {m.group()!r}->{new[:20]!r}")
    elif roll < 0.2 and "-n" in case.scenario.args:
        case.count = rng.choice(_HUGE_COUNTS)
        case.ops.append(f"-n {case.count[:24]}")
    elif roll < 0.26:
        case.stream = rng.choice(("full", "broken", "none"))
        case.ops.append(f"standard output {case.stream}")


def _place(kind: str, seed: Path) -> str:
    return LAYOUT[kind].format(ext=_suffix(seed))


def prepare(case: Case, work: Path) -> list[str]:
    """Write the inputs of ``case`` into the empty directory ``work``; return the arguments."""
    paths: dict[str, Path] = {}
    shutil.copytree(FIXTURES / "curobo_classic" / "spheres", work / "curobo" / "spheres")
    (work / "out").mkdir()
    for kind, seeds in SEEDS.items():
        seed = case.seed_file if kind == case.kind else seeds[0]
        dest = work / _place(kind, seed)
        dest.parent.mkdir(parents=True, exist_ok=True)
        if kind == case.kind and case.special is not None:
            dest.unlink(missing_ok=True)
            _special(case.special, dest)
        elif kind == case.kind:
            assert case.text is not None
            dest.write_bytes(case.text)
        else:
            shutil.copyfile(seed, dest)
        paths[kind] = dest
    shutil.copyfile(SEEDS["xrdf"][0], work / "other.xrdf")
    paths["other"] = work / "other.xrdf"
    args: list[str] = []
    for i, a in enumerate(case.scenario.args):
        if case.count is not None and i > 0 and case.scenario.args[i - 1] == "-n":
            args.append(case.count)
            continue
        if a.startswith("{"):
            args.append(str(paths[a[1:-1]]))
        elif a.startswith("@"):
            suffix = {"viz-mimic": ".png", "viz": ".mcap", "report-mimic": ".png"}.get(
                case.scenario.name, ".out"
            )
            args.append(str(work / "out" / (a[1:] + suffix)))
        else:
            args.append(a)
    return args


def _special(how: str, dest: Path) -> None:
    if how == "directory":
        dest.mkdir()
    elif how == "fifo":
        os.mkfifo(dest)
    else:
        dest.symlink_to("/dev/zero")


def snapshot(work: Path) -> dict[str, str]:
    """A digest of every input under ``work`` (outputs in ``work/out`` left out)."""
    out: dict[str, str] = {}
    for p in sorted(work.rglob("*")):
        rel = p.relative_to(work).as_posix()
        if rel.startswith("out/") or rel == "out":
            continue
        if p.is_symlink():
            out[rel] = "link:" + os.readlink(p)
        elif p.is_file():
            out[rel] = hashlib.sha256(p.read_bytes()).hexdigest()
        else:
            out[rel] = "dir" if p.is_dir() else "special"
    return out


@dataclass
class Outcome:
    """What one run did; ``problems`` is empty when every promise held."""

    case: Case
    exit_code: int
    output: str
    problems: list[str] = field(default_factory=list)

    def summary(self) -> str:
        c = self.case
        return (
            f"case {c.number}: {c.scenario.name}, {c.kind} from {c.seed_file.name} "
            f"({'; '.join(c.ops)}): exit {self.exit_code}; {'; '.join(self.problems)}"
        )


Invoke = Callable[[Sequence[str]], tuple[int, str, BaseException | None, str]]


def invoke_in_process(args: Sequence[str]) -> tuple[int, str, BaseException | None, str]:
    """Run ``xrdf ARGS`` like :func:`xrdf_tools.cli.main` would: ``(exit code, stdout+stderr,
    escaped exception or None, its traceback text)``."""
    from typer.testing import CliRunner

    from xrdf_tools.cli import app
    from xrdf_tools.util.errors import XrdfToolsError

    res = CliRunner().invoke(app, list(args), catch_exceptions=True)
    exc = res.exception
    if exc is None or isinstance(exc, SystemExit):
        return res.exit_code, res.output, None, ""
    if isinstance(exc, XrdfToolsError):  # main() prints these as one line and exits 2
        return 2, res.output + f"error: {exc}\n", None, ""
    tb = "".join(traceback.format_exception(*res.exc_info)) if res.exc_info else repr(exc)
    return res.exit_code, res.output, exc, tb


#: Appended to the output by :func:`invoke_with_faulty_stdout` when output was lost.
OUTPUT_LOST = "\n[fuzz] output written to a faulty standard output, yet the exit code is not 2"


class _FaultyStdout(io.TextIOBase):
    """A standard output that fails every write: a full disk or a reader that has gone."""

    def __init__(self, how: str) -> None:
        self.how = how
        self.attempted = False

    def writable(self) -> bool:
        return True

    def write(self, s: str) -> int:
        if not s:
            return 0
        self.attempted = True
        if self.how == "full":
            raise OSError(errno.ENOSPC, "No space left on device")
        raise OSError(errno.EPIPE, "Broken pipe")


def invoke_with_faulty_stdout(
    args: Sequence[str], how: str
) -> tuple[int, str, BaseException | None, str]:
    """Like :func:`invoke_in_process`, with standard output failing (``full``, ``broken``) or
    closed (``none``): whatever the command wrote there must end it with exit code 2."""
    from xrdf_tools.cli import app
    from xrdf_tools.util.errors import XrdfToolsError

    stdout = None if how == "none" else _FaultyStdout(how)
    err = io.StringIO()
    code: int
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(err):  # type: ignore[type-var]
        try:
            app(list(args), standalone_mode=True)
            code = 0
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
        except XrdfToolsError as e:
            err.write(f"error: {e}\n")
            code = 2
        except BaseException as e:
            return 1, err.getvalue(), e, "".join(traceback.format_exception(e))
    output = err.getvalue()
    if isinstance(stdout, _FaultyStdout) and stdout.attempted and code != 2:
        output += OUTPUT_LOST
    return code, output, None, ""


def check(case: Case, code: int, output: str, exc: BaseException | None, tb: str) -> Outcome:
    """Judge one run against the promises (see the module docstring)."""
    out = Outcome(case, code, output)
    if exc is not None:
        last = tb.strip().splitlines()[-1] if tb.strip() else repr(exc)
        out.problems.append(f"traceback: {last}")
    if "Traceback (most recent call last)" in output:
        out.problems.append("traceback in output")
    if "internal-error" in output:
        out.problems.append("internal-error finding")
    if code not in (0, 1, 2):
        out.problems.append(f"exit code {code}")
    if OUTPUT_LOST in output:
        out.problems.append("output lost: written to a faulty standard output with exit 0/1")
    return out


def run_case(case: Case, work: Path, invoke: Invoke = invoke_in_process) -> Outcome:
    """Prepare ``case`` in the empty directory ``work``, run it from there, judge it."""
    args = prepare(case, work)
    before = snapshot(work)
    cwd = os.getcwd()
    os.chdir(work)  # lint discovers work/.xrdf-lint.yaml, and nothing above it
    try:
        if case.stream is not None and invoke is invoke_in_process:
            code, output, exc, tb = invoke_with_faulty_stdout(args, case.stream)
        else:
            code, output, exc, tb = invoke(args)
    finally:
        os.chdir(cwd)
    outcome = check(case, code, output, exc, tb)
    if snapshot(work) != before:
        outcome.problems.append("an input file changed")
    if case.special is None:
        damaged = str(work / _place(case.kind, case.seed_file))
        outcome.problems += [f"no location: {e}" for e in unlocated_errors(output, damaged)]
    return outcome


#: Errors about a file as a whole, which have no line to give.
WHOLE_FILE = re.compile(
    r"not found|does not exist|is empty|larger than the|not a xacro file|no such file|"
    r"maximum recursion depth|nothing to expand",
    re.IGNORECASE,
)


def unlocated_errors(output: str, path: str) -> list[str]:
    """``error:`` lines that blame ``path`` without a line number (and are not about the file
    as a whole): an input error must say where in the file it is."""
    prefix = f"error: {path}: "
    return [
        line
        for line in output.splitlines()
        if line.startswith(prefix) and not WHOLE_FILE.search(line)
    ]
