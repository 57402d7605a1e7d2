"""Only the editor's own page may drive ``xrdf edit``: not another web page open in the same
browser (a websocket to 127.0.0.1 from ``http://evil.example``), not a DNS-rebinding page.

The attack, as such a page would run it: connect to the editor's websocket with viser's
subprotocol, read the GUI's buttons from the messages the server sends, say "I am a client"
(a camera message), and press Save... and Confirm save. The same client from the editor's own
origin does all of it: that is what another origin could do before the guard.

Real inputs: the example-robot-data Panda with fixtures/panda/panda.xrdf, served in this
process (viser's threads); the client is the ``websockets`` library viser runs on.
"""

from __future__ import annotations

import asyncio
import http.client
import shutil
from collections.abc import Iterator
from typing import Any

import pytest

from tests.browser import free_port
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.edit import EditState
from xrdf_tools.edit.guard import RequestGuard, own_names, refusal, start_guarded
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.util.errors import MissingDependencyError
from xrdf_tools.xrdf.io import load_xrdf

viser = pytest.importorskip("viser", reason="xrdf edit needs viser (the edit extra)")
websockets_client = pytest.importorskip("websockets.asyncio.client")

SAVE = ("Save…", "Confirm save")


@pytest.fixture(scope="module")
def page(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    from xrdf_tools.edit.page import EditorPage

    target = tmp_path_factory.mktemp("edit") / "panda.xrdf"
    shutil.copy(FIXTURES / "panda" / "panda.xrdf", target)
    robot = load_robot(robot_urdf("panda"))
    served = EditorPage(robot, EditState.start(load_xrdf(target)), target=target, port=free_port())
    try:
        yield served
    finally:
        served.close()


def press(url: str, origin: str | None, labels: tuple[str, ...]) -> None:
    """Drive the page as its client would: connect, find the buttons, press ``labels``."""
    asyncio.run(_press(url.replace("http://", "ws://"), origin, labels))


async def _press(url: str, origin: str | None, labels: tuple[str, ...]) -> None:
    import msgspec
    import zstandard
    from viser import _messages

    def send(message: Any) -> Any:
        return ws.send(msgspec.msgpack.encode(message.as_serializable_dict()))

    async def received() -> list[dict[str, Any]]:
        raw = await asyncio.wait_for(ws.recv(), 10)
        assert isinstance(raw, bytes)
        size, packed = int.from_bytes(raw[:8], "little"), int.from_bytes(raw[8:16], "little")
        inner = zstandard.ZstdDecompressor().decompress(raw[16 : 16 + packed], size)
        messages: list[dict[str, Any]] = msgspec.msgpack.decode(inner)["messages"]
        return messages

    async def shown(uuid: str) -> None:
        while not any(
            m["type"] == "GuiUpdateMessage" and m["uuid"] == uuid and m["updates"].get("visible")
            for m in await received()
        ):
            pass

    async with websockets_client.connect(
        url,
        origin=origin,  # type: ignore[arg-type]
        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
        open_timeout=10,
    ) as ws:
        buttons: dict[str, str] = {}
        while not set(labels) <= buttons.keys():
            for m in await received():
                if m["type"] == "GuiButtonMessage":
                    buttons[m["props"]["label"]] = m["uuid"]
        z, one = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0)
        await send(_messages.ViewerCameraMessage(one, (1, 1, 1), 1.0, 0.01, 9.0, 48, 64, z, z))
        for i, label in enumerate(labels):
            await send(_messages.GuiUpdateMessage(buttons[label], {"value": True}))
            if i + 1 < len(labels):
                # pressed once the page shows it, as a person would: viser runs each press on
                # a thread pool, so a press sent at once may be handled before this one
                await shown(buttons[labels[i + 1]])
        await asyncio.sleep(0.2)  # the server takes the last press before the client leaves


def said(page: Any, message: str) -> bool:
    """Wait (at most 10 s) until the page's message starts with ``message``."""
    for _ in range(200):
        if page.message.startswith(message):
            return True
        asyncio.run(asyncio.sleep(0.05))
    return False


def get(page: Any, host: str) -> int:
    """The HTTP status of the page's index for a request naming ``host``."""
    conn = http.client.HTTPConnection("127.0.0.1", page.server.get_port(), timeout=10)
    try:
        conn.request("GET", "/", headers={"Host": host})
        return conn.getresponse().status
    finally:
        conn.close()


@pytest.mark.parametrize(
    "origin",
    [
        "http://evil.example",
        "null",  # a sandboxed frame or a file:// page
        "http://localhost:3000",  # another local server's page
        "https://127.0.0.1:{port}",
    ],
)
def test_a_page_from_elsewhere_cannot_connect_nor_save(page: Any, origin: str) -> None:
    before = page.target.read_bytes()
    page.say("")
    with pytest.raises(websockets_client.InvalidStatus) as refused:
        press(page.url, origin.format(port=page.server.get_port()), SAVE)
    assert refused.value.response.status_code == 403
    assert page.message == ""
    assert page.target.read_bytes() == before


@pytest.mark.parametrize("origin", ["{url}", "http://localhost:{port}", None])
def test_the_editors_own_page_and_programs_drive_it(page: Any, origin: str | None) -> None:
    # what any page could do before: its client presses Save... and Confirm save
    page.target.write_bytes(page.target.read_bytes() + b"\n# changed by hand\n")
    shown = None if origin is None else origin.format(url=page.url, port=page.server.get_port())
    press(page.url, shown, SAVE)
    assert said(page, "saved "), page.message
    assert b"changed by hand" not in page.target.read_bytes()


def test_a_rebinding_page_gets_no_file_from_the_server(page: Any) -> None:
    port = page.server.get_port()
    assert get(page, f"evil.example:{port}") == 403
    assert get(page, "127.0.0.1.evil.example") == 403
    for host in (f"127.0.0.1:{port}", f"localhost:{port}", f"[::1]:{port}", "localhost:9000"):
        assert get(page, host) == 200, host  # any port: an SSH tunnel may forward another


def test_each_refusal_is_heard_once(page: Any) -> None:
    heard: list[str] = []
    page.guard.on_refused = heard.append
    try:
        for _ in range(3):
            assert get(page, "evil.example") == 403
    finally:
        page.guard.on_refused = None
    assert heard == [
        "refused a request for evil.example: not an address of this editor (a page whose "
        "name now resolves here?); open it at one of 127.0.0.1, ::1, localhost"
    ]


@pytest.mark.parametrize(
    ("hosts", "origins", "refused"),
    [
        (["127.0.0.1:8080"], [], None),
        (["LOCALHOST:8080"], ["http://127.0.0.1:8080"], None),
        (["[::1]:8080"], ["http://[::1]:8080"], None),
        (["localhost"], ["http://localhost"], None),
        (["localhost"], ["http://localhost:80"], None),
        # a fully qualified name, an address written long: a browser at the editor's page
        (["localhost.:8080"], ["http://LOCALHOST.:8080"], None),
        (["[0:0:0:0:0:0:0:1]:8080"], ["http://[::1]:8080"], None),
        (["[::ffff:7f00:1]:8080"], ["http://[::ffff:7f00:1]:8080"], None),
        (["localhost..:8080"], [], "refused a request for localhost..:"),
        (["[1:2]:8080"], [], "refused a request without one valid Host"),
        (["127.0.0.1:8080"], ["http://127.0.0.1:8081"], "refused a connection from a page"),
        (["127.0.0.1:8080"], ["http://evil.example:8080"], "refused a connection from a page"),
        (["127.0.0.1:8080"], ["http://127.0.0.1:8080/x"], "refused a connection from a page"),
        (["127.0.0.1:8080"], ["http://a@127.0.0.1:8080"], "refused a connection from a page"),
        (
            ["127.0.0.1:8080"],
            ["http://127.0.0.1:8080"] * 2,
            "refused a connection from a page at 2",
        ),
        (["127.0.0.1:8080"], [""], "refused a connection from a page at : only"),
        (["evil.example:8080"], ["http://evil.example:8080"], "refused a request for evil"),
        (["127.0.0.1:99999"], [], "refused a request without one valid Host"),
        ([], [], "refused a request without one valid Host"),
        (["127.0.0.1", "localhost"], [], "refused a request without one valid Host"),
        (["127.0.0.1\n:80"], [], "refused a request without one valid Host"),
    ],
)
def test_refusal(hosts: list[str], origins: list[str], refused: str | None) -> None:
    why = refusal(hosts, origins, own_names("127.0.0.1"))
    assert why == refused if refused is None else why is not None and why.startswith(refused)


def test_own_names_are_the_loopback_names_and_the_host_listened_on() -> None:
    import socket

    assert own_names("127.0.0.1") == {"127.0.0.1", "localhost", "::1"}
    assert own_names("Robot-PC.lan") == {"127.0.0.1", "localhost", "::1", "robot-pc.lan"}
    assert own_names("Robot-PC.lan.") == own_names("Robot-PC.lan")
    assert own_names("[0::1]") == own_names("127.0.0.1")
    assert own_names("[::]") == {"127.0.0.1", "localhost", "::1", socket.gethostname().lower()}


def test_a_viser_that_serves_another_way_is_not_served_unguarded() -> None:
    closed: list[object] = []
    with pytest.raises(MissingDependencyError, match="cannot keep other web pages"):
        start_guarded(object, RequestGuard("127.0.0.1"), close=closed.append)
    assert len(closed) == 1
