"""Whether a robot (or SRDF) file needs xacro: it declares and uses the xacro namespace, or an
attribute holds a substitution (``$(find pkg)``, ``$(arg x)``, ``$(optenv VAR default)``...).
xacro evaluates those in any file, with or without its namespace; simulators ship such files
as plain ``.urdf`` (pybullet's husky has ``xyz="$(optenv HUSKY_IMU_XYZ 0.19 0 0.149)"``), which
ROS expands before reading. A ``${...}`` expression alone does not count: URDFs written out of
a xacro keep some where no reader looks (Talos' ``<safety_controller>``), and expanding
those would fail on properties defined nowhere.
"""

from __future__ import annotations

import re

__all__ = ["uses_xacro"]

_SUBSTITUTION_IN_ATTRIBUTE = re.compile(
    rb"""=\s*(?:"[^"<]*|'[^'<]*)\$\((?:find|arg|optenv|env|eval|dirname|cwd|anon)[\s)]"""
)

_COMMENT = re.compile(rb"<!--.*?-->", re.DOTALL)


def uses_xacro(data: bytes) -> bool:
    """The bytes of a robot (or SRDF) file declare the xacro namespace and use it, or hold a
    xacro substitution in an attribute, which only xacro can evaluate; comments left out (a
    URDF written by xacro keeps ``xmlns:xacro`` and may keep a ``<xacro:...>`` element
    commented out: Talos' ``talos_full_v2.urdf``)."""
    if b"<xacro:" not in data and b"$" not in data:
        return False
    text = _COMMENT.sub(b"", data)
    if b"xmlns:xacro" in data[:4096] and b"<xacro:" in text:
        return True
    if b"$" not in text:
        return False
    return _SUBSTITUTION_IN_ATTRIBUTE.search(text) is not None
