"""The page's messages where the user is: refusals, warnings and saves as toasts in every open
tab (one at a time), edits made only in the Document panel's record."""

from __future__ import annotations

from typing import Any

import pytest

from xrdf_tools.edit.notices import Notices, tone


@pytest.mark.parametrize(
    ("message", "kind"),
    [
        ("not set: Buffer (m) takes 0 to 0.5 m, not 7", "refusal"),
        ("not done: radius must be > 0", "refusal"),
        ("not saved: disk full", "refusal"),
        ("select a sphere first (click it, or choose it under Spheres)", "refusal"),
        ("read-only: saving is disabled (started with --readonly)", "refusal"),
        ("done: delete panda_link7[0]; warning: 'panda_link7' has collision geometry", "warning"),
        ("done: took j into the c-space, but it moves no tool frame", "warning"),
        ("saved /tmp/panda.xrdf", "saved"),
        ("no change: put the c-space in URDF order (the document has it already)", "note"),
        ("done: radius of panda_link3[0] to 0.0500", None),
        ("undone: radius of panda_link3[0] to 0.0500", None),
        ("redone: radius of panda_link3[0] to 0.0500", None),
    ],
)
def test_what_is_shown_over_the_view(message: str, kind: str | None) -> None:
    assert tone(message) == kind


class Toast:
    def __init__(self, shown: list[Any], body: str, color: str) -> None:
        self.shown, self.body, self.color = shown, body, color

    def remove(self) -> None:
        self.shown.remove(self)


class Client:
    def __init__(self) -> None:
        self.toasts: list[Toast] = []

    def add_notification(self, title: str, body: str, **options: Any) -> Toast:
        assert title == "" and options["auto_close_seconds"] > 0
        toast = Toast(self.toasts, body, options["color"])
        self.toasts.append(toast)
        return toast


def test_one_toast_at_a_time_in_every_tab() -> None:
    tabs = {1: Client(), 2: Client()}
    server = type("Server", (), {"get_clients": lambda self: dict(tabs)})()
    notices = Notices(server)
    notices.show("not set: Buffer (m) takes 0 to 0.5 m, not 7")
    notices.show("done: buffer of panda_link3 to 0.005")  # recorded only
    assert [(t.body, t.color) for t in tabs[1].toasts] == [
        ("not set: Buffer (m) takes 0 to 0.5 m, not 7", "red")
    ]
    notices.show("saved panda.xrdf")  # replaces the last one
    del tabs[2]  # a tab closed
    notices.show("no change: nothing to undo")
    assert [(t.body, t.color) for t in tabs[1].toasts] == [("no change: nothing to undo", "blue")]
    assert set(notices.shown) == {1}
