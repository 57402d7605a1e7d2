"""The xacro arguments a command line gives that the expansion never reads.

xacro ignores a ``name:=value`` mapping that no ``<xacro:arg>`` declares and no ``$(arg)``
reads, so a misspelt ``--xacro-arg ee_typ:=dd`` silently expands the default robot.
:class:`ReadArgs` is the mapping xacro is given: it records every name xacro looks up (a
declaration asks whether the name is given, ``$(arg)`` and ``xacro.arg()`` read it), and
:func:`unread_arg_warnings` names each given argument xacro never asked for.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..diagnostics import Diagnostic, Severity
from ..util.errors import did_you_mean, shown_text
from ..util.text import name_list

__all__ = ["RULE_UNREAD_ARG", "ReadArgs", "unread_arg_warnings"]

RULE_UNREAD_ARG = "xacro-arg-unread"


class ReadArgs(dict[str, str]):
    """A ``dict`` of xacro arguments that remembers the names looked up in it."""

    def __init__(self, given: Mapping[str, str]) -> None:
        super().__init__(given)
        self.asked: set[str] = set()

    def __contains__(self, key: object) -> bool:
        if isinstance(key, str):
            self.asked.add(key)
        return super().__contains__(key)

    def __getitem__(self, key: str) -> str:
        self.asked.add(key)
        return super().__getitem__(key)

    def get(self, key: str, default: Any = None) -> Any:
        self.asked.add(key)
        return super().get(key, default)


def unread_arg_warnings(path: str, given: Mapping[str, str], read: ReadArgs) -> list[Diagnostic]:
    """A warning per argument of ``given`` that the expansion never looked up in ``read``."""
    known = sorted(read.asked)
    shown = name_list(known)
    return [
        Diagnostic(
            path,
            None,
            None,
            RULE_UNREAD_ARG,
            Severity.WARNING,
            f"--xacro-arg {name}:={shown_text(value)}: no <xacro:arg> or $(arg) of the expansion "
            f"reads '{name}', so it changes nothing"
            + (f" (arguments read: {shown})" if known else "")
            + did_you_mean(name, known),
            "",
        )
        for name, value in given.items()
        if name not in read.asked
    ]
