"""One shape vocabulary, two walkers: ``check_shape`` stops at the first departure (readers of
foreign YAML), ``lint.schema.walk`` reports every one (lint), on the same ``Shape`` values."""

from __future__ import annotations

import pytest

from xrdf_tools.lint.schema import walk
from xrdf_tools.util.errors import SchemaError
from xrdf_tools.xrdf.shape import CSPACE, GROUP_REF
from xrdf_tools.yaml.io import parse_yaml
from xrdf_tools.yaml.shape import NAME, NUMBER, check_shape, list_of, map_of

CSPACE_TEXT = "joint_names: [a, 5, '']\nacceleration_limits: [1, x]\nextra: 1\n"


def test_first_error_and_all_errors_on_the_xrdf_cspace_shape() -> None:
    doc = parse_yaml(CSPACE_TEXT, "c.yaml")
    with pytest.raises(SchemaError) as e:
        check_shape(doc.root, CSPACE, path="c.yaml", error=SchemaError, key_path="cspace")
    # the first departure in document order; a number is a name, an unknown key is the caller's
    assert str(e.value) == "c.yaml:1:21: cspace.joint_names[2] must be a name, not the string ''"
    found = [
        (ev.kind, ev.node.line, ev.node.col, ev.key_path) for ev in walk(doc.root, CSPACE, "cspace")
    ]
    assert found == [
        ("missing", 1, 1, "cspace"),
        ("type", 1, 21, "cspace.joint_names[2]"),
        ("type", 2, 26, "cspace.acceleration_limits[1]"),
        ("unknown", 3, 1, "cspace.extra"),
    ]


def test_the_helpers_make_the_shared_kinds() -> None:
    assert list_of(NAME) == CSPACE.fields["joint_names"]  # the XRDF's list of names
    assert NUMBER.kind == CSPACE.fields["jerk_limits"].values.kind == "num"  # type: ignore[union-attr]
    assert map_of(NAME).kind == "dict" and map_of(None, fields={"a": NAME}).kind == "fields"
    doc = parse_yaml("g: [x]\n", "g.yaml")
    with pytest.raises(ValueError, match="does not take 'groupref' shapes"):
        check_shape(doc.root, map_of(GROUP_REF), path="g.yaml", error=SchemaError)
