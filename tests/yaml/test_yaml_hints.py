"""A YAML syntax error says what to check: the hand edits that break an XRDF (a tab, a line
indented one space off, a missing ':', an unclosed '[') each get the fix beside libyaml's words,
and a URDF or SRDF given where YAML is read is named as XML at 1:1 instead of the YAML error
its text happens to make somewhere inside."""

from __future__ import annotations

import pytest

from tests.paths import FIXTURES
from xrdf_tools.util.errors import XrdfToolsError, YamlError
from xrdf_tools.xrdf.read import load_xrdf
from xrdf_tools.yaml.io import parse_yaml

GOOD = (
    "format: xrdf\n"
    "format_version: 1.0\n"
    "cspace:\n"
    "  joint_names:\n"
    "    - a\n"
    "    - b\n"
    "  acceleration_limits: [1.0, 1.0]\n"
)


def _error(text: str) -> YamlError:
    with pytest.raises(YamlError) as info:
        parse_yaml(text, "r.xrdf")
    return info.value


@pytest.mark.parametrize(
    ("edit", "where", "hint"),
    [
        (("    - b", "   - b"), "r.xrdf:6:4:", "against the lines above (spaces only)"),
        (("    - b", "\t- b"), "r.xrdf:6:1:", "YAML indents with spaces: replace the tab"),
        (
            ("format_version: 1.0", "format_version 1.0"),
            "r.xrdf:3:1:",  # where libyaml gave up; the hint names the line to fix
            "the key that starts on line 2 needs ':' and a space after it",
        ),
        (("1.0, 1.0]", "1.0, 1.0"), "r.xrdf:8:1:", "the '[' on line 7, column 24 is not closed"),
        (
            ("format_version:", "  format_version:"),
            "r.xrdf:2:17:",
            "or quote a value that contains ': '",
        ),
    ],
)
def test_a_hand_edit_gets_what_to_check(edit: tuple[str, str], where: str, hint: str) -> None:
    parse_yaml(GOOD)  # the file before the edit is fine
    err = _error(GOOD.replace(*edit))
    assert str(err).startswith(where + " YAML syntax error: "), str(err)
    assert str(err).endswith(hint), str(err)
    assert "\n" not in str(err)


def test_an_error_without_a_usual_cause_keeps_libyaml_words_alone() -> None:
    err = _error("a: 'unclosed\n")
    assert "; " not in str(err).split("YAML syntax error: ")[1], str(err)


@pytest.mark.parametrize(
    "path", [FIXTURES / "demo_arm" / "demo_arm.urdf", FIXTURES / "demo_arm" / "demo_arm.srdf"]
)
def test_an_xml_file_read_as_an_xrdf_is_named_at_its_start(path: object) -> None:
    """The URDF's text is a YAML error on line 2; the SRDF's a valid YAML string (the top
    level must be a mapping, not the string '<?xml ...'): both are named as XML, at 1:1."""
    with pytest.raises(XrdfToolsError) as info:
        load_xrdf(str(path))
    assert str(info.value) == (f"{path}:1:1: an XML document (a URDF, xacro or SRDF?), not YAML"), (
        str(info.value)
    )
