"""The page's messages where the user is: a toast over the 3D view, as well as the record at
the top of the Document panel.

The Document panel is out of sight while the user types in the C-space or Mask panel, so a
refusal there went unseen. Every message the page says is kept in the Document panel; those
the user must see (a refusal, a warning, a save's result, a change that was not needed) also
show as a viser notification in every open tab, one at a time (the next replaces it), closing
by itself. An edit made (``done: …``, ``undone: …``, ``redone: …``) shows in the view and is
only recorded, unless it carries a warning.

The page's messages keep one convention, which :func:`tone` reads: a refusal starts with
``not `` (``not done:``, ``not set:``, ``not saved:``, ``not moved:``, ``not posed:``), a
warning says ``warning:`` or ``, but``.
"""

from __future__ import annotations

from typing import Any, Literal

__all__ = ["Notices", "tone"]

Tone = Literal["refusal", "warning", "saved", "note"]

#: How long a toast stays, seconds (it can be closed sooner; the Document panel keeps it).
SHOWN_S: dict[Tone, float] = {"refusal": 10.0, "warning": 10.0, "saved": 5.0, "note": 6.0}
#: Mantine colours of the toasts.
COLORS: dict[Tone, str] = {"refusal": "red", "warning": "yellow", "saved": "green", "note": "blue"}
#: Messages of edits made: the view shows them.
RECORDED_ONLY = ("done: ", "undone: ", "redone: ")
#: How a refusal begins.
REFUSALS = ("not ", "read-only", "select ", "this robot has no")


def tone(message: str) -> Tone | None:
    """What ``message`` is, None when it is only recorded (an edit made, without warning)."""
    if "warning:" in message or ", but " in message:
        return "warning"
    if message.startswith(RECORDED_ONLY):
        return None
    if message.startswith(REFUSALS):
        return "refusal"
    if message.startswith("saved "):
        return "saved"
    return "note"


class Notices:
    """The toasts of one viser server: one shown at a time in each tab."""

    def __init__(self, server: Any) -> None:
        self.server = server
        #: The toast shown in each tab (client id), replaced by the next.
        self.shown: dict[int, Any] = {}

    def show(self, message: str) -> None:
        """Show ``message`` in every open tab if :func:`tone` says the user must see it."""
        kind = tone(message)
        if kind is None or not message:
            return
        clients = self.server.get_clients()
        for gone in set(self.shown) - set(clients):
            del self.shown[gone]
        for cid, client in clients.items():
            old = self.shown.pop(cid, None)
            if old is not None:
                old.remove()
            self.shown[cid] = client.add_notification(
                "",
                message,
                auto_close_seconds=SHOWN_S[kind],
                color=COLORS[kind],
            )
