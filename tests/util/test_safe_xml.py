"""The one XML parser (xrdf_tools.util.safe_xml), through each of its three readers: the URDF,
the SRDF read by convert, and the SRDF that ``export srdf --merge`` edits."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pytest

from xrdf_tools.convert.sources.srdf import parse_srdf
from xrdf_tools.export.srdf_xml import XmlDocument
from xrdf_tools.robot.urdf_source import parse_robot
from xrdf_tools.util.errors import XrdfToolsError
from xrdf_tools.util.safe_xml import XmlSyntaxError, parse_xml

_ROBOT = '<robot name="r">{}<link name="a"/></robot>'


def _read_urdf(text: str) -> object:
    return parse_robot(text, "r.urdf")


def _read_srdf(text: str) -> object:
    return parse_srdf(text, "r.srdf")


def _merge_srdf(text: str) -> object:
    return XmlDocument.parse(text, "r.srdf")


READERS: dict[str, Callable[[str], object]] = {
    "urdf": _read_urdf,
    "srdf": _read_srdf,
    "srdf-merge": _merge_srdf,
}


def _bomb(levels: int) -> str:
    ents = '<!ENTITY a0 "xxxxxxxxxx">' + "".join(
        f'<!ENTITY a{i} "{f"&a{i - 1};" * 10}">' for i in range(1, levels + 1)
    )
    return f"<!DOCTYPE robot [{ents}]>\n" + _ROBOT.format(f"<link name='&a{levels};'/>")


@pytest.mark.parametrize("reader", READERS)
def test_an_entity_bomb_is_refused_at_once_by_every_reader(reader: str) -> None:
    start = time.perf_counter()
    with pytest.raises(XrdfToolsError, match="amplification") as e:
        READERS[reader](_bomb(9))  # 10**10 characters if it were expanded
    assert time.perf_counter() - start < 2.0
    assert e.value.line == 2 and "\n" not in str(e.value)


@pytest.mark.parametrize("reader", READERS)
def test_an_external_entity_is_never_read(reader: str, tmp_path: Path) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    doctype = f'<!DOCTYPE robot [<!ENTITY e SYSTEM "{secret.as_uri()}">]>\n'
    text = doctype + _ROBOT.format("<group name='g'><link name='a'/></group>&e;")
    result = READERS[reader](text)
    root = parse_xml(text.encode())
    from lxml import etree

    assert b"TOP-SECRET" not in etree.tostring(root)
    assert "TOP-SECRET" not in repr(result)


@pytest.mark.parametrize("reader", READERS)
def test_nesting_beyond_libxml2s_default_limit_is_refused(reader: str) -> None:
    deep = "<a>" * 300 + "</a>" * 300
    with pytest.raises(XrdfToolsError, match="Excessive depth") as e:
        READERS[reader](_ROBOT.format(deep))
    assert e.value.line == 1


def test_the_urdf_message_puts_the_position_in_front_the_srdf_message_keeps_libxml2s() -> None:
    text = '<robot name="r">\n  <link name="a">\n</robot>\n'
    mismatch = "Opening and ending tag mismatch: link line 2 and robot"
    with pytest.raises(XrdfToolsError) as urdf:
        _read_urdf(text)
    assert str(urdf.value) == f"r.urdf:3:9: malformed XML: {mismatch}"
    for read in (_read_srdf, _merge_srdf):
        with pytest.raises(XrdfToolsError) as srdf:
            read(text)
        assert str(srdf.value) == f"r.srdf:3: malformed SRDF XML: {mismatch}, line 3, column 9"


def test_the_syntax_error_carries_libxml2s_words_and_position() -> None:
    with pytest.raises(XmlSyntaxError) as e:
        parse_xml(b"<a>\n<b></a>")
    assert (e.value.line, e.value.col) == (2, 8)
    assert e.value.verbatim == e.value.reason + ", line 2, column 8"
    assert str(e.value) == e.value.verbatim


def test_comments_and_cdata_are_kept_only_when_asked() -> None:
    from lxml import etree

    data = b"<a><!-- c --><b><![CDATA[x<y]]></b><?pi z?></a>"
    assert etree.tostring(parse_xml(data)) == b"<a><!-- c --><b>x&lt;y</b><?pi z?></a>"
    assert etree.tostring(parse_xml(data, keep_comments=False)) == b"<a><b>x&lt;y</b><?pi z?></a>"
    kept = parse_xml(data, keep_cdata=True)
    assert etree.tostring(kept) == data


def test_an_srdf_given_as_text_may_declare_another_encoding() -> None:
    text = '<?xml version="1.0" encoding="ISO-8859-1"?>\n<robot name="bras_é"/>\n'
    assert parse_srdf(text, "r.srdf").robot_name == "bras_é"
    assert XmlDocument.parse(text, "r.srdf").root.get("name") == "bras_é"
