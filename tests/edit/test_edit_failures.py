"""``xrdf edit`` when things go wrong: an address it cannot listen on, a save that cannot be
written, a file changed under the page, a document changed after its review. Each failure is
one line (in the page and on the terminal), and nothing the user had is lost.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.browser import free_port
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.edit import EditState, SetRadius
from xrdf_tools.edit.guard import check_address
from xrdf_tools.edit.typed import TypedNumber, parse_typed
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.util.errors import InputError
from xrdf_tools.xrdf.io import load_xrdf

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
#: An address of no machine here (TEST-NET-1, RFC 5737).
ELSEWHERE = "192.0.2.1"

pytest.importorskip("viser", reason="xrdf edit needs viser (the edit extra)")
websockets_client = pytest.importorskip("websockets.asyncio.client")
websockets_exceptions = pytest.importorskip("websockets.exceptions")


@pytest.mark.parametrize(
    ("host", "reason"),
    [(ELSEWHERE, "Cannot assign requested address"), ("no such host", "")],
)
def test_an_address_no_server_can_listen_on_is_one_line(host: str, reason: str) -> None:
    with pytest.raises(InputError, match=f"^cannot serve on {host}: {reason}"):
        check_address(host)
    for own in ("127.0.0.1", "localhost", ""):
        check_address(own)


def test_edit_on_another_machines_address_says_so_instead_of_hanging(tmp_path: Path) -> None:
    """viser tried a thousand ports, then waited for a server that never started."""
    target = tmp_path / "panda.xrdf"
    target.write_bytes(PANDA_XRDF.read_bytes())
    args = [str(target), "--urdf", str(robot_urdf("panda")), "--host", ELSEWHERE]
    args += ["--port", str(free_port()), "--no-browser"]
    cli = [sys.executable, "-c", "from xrdf_tools.cli import main; main()", "edit", *args]
    try:
        r = subprocess.run(cli, capture_output=True, text=True, timeout=30)
    except subprocess.TimeoutExpired:
        pytest.fail(f"xrdf edit --host {ELSEWHERE} hung")
    assert r.returncode == 2
    assert r.stderr.splitlines() == [
        f"error: cannot serve on {ELSEWHERE}: Cannot assign requested address "
        "(not an address of this machine?)"
    ]
    assert target.read_bytes() == PANDA_XRDF.read_bytes()


# --- what a client may send ------------------------------------------------------------------
@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Any, list[str]]]:
    """The editor on a copy of the Panda XRDF, and what it reported for the terminal."""
    target = tmp_path_factory.mktemp("edit") / "panda.xrdf"
    shutil.copy(PANDA_XRDF, target)
    page, heard = _panda_editor(target)
    try:
        yield page, heard
    finally:
        page.close()


def _panda_editor(target: Path) -> tuple[Any, list[str]]:
    """The editor on the Panda XRDF at ``target``, and the list its terminal lines go to."""
    from xrdf_tools.edit.page import EditorPage

    heard: list[str] = []
    page = EditorPage(
        load_robot(robot_urdf("panda")),
        EditState.start(load_xrdf(target)),
        target=target,
        port=free_port(),
        on_refused=heard.append,
    )
    return page, heard


def send(url: str, build: Callable[[dict[str, str]], bytes]) -> None:
    """Connect as the page's client does (no Origin: a program), say "I am a client" (a
    camera message), and send ``build(uuids of the controls by label)``."""
    asyncio.run(_send(url.replace("http://", "ws://"), build))


async def _send(url: str, build: Callable[[dict[str, str]], bytes]) -> None:
    import msgspec
    import viser
    import zstandard
    from viser import _messages

    async with websockets_client.connect(
        url,
        subprotocols=[f"viser-v{viser.__version__}"],
        open_timeout=10,  # type: ignore[list-item]
    ) as ws:
        uuids: dict[str, str] = {}
        while True:  # the page's controls, until it has sent them all
            try:
                raw = await asyncio.wait_for(ws.recv(), 1 if "Scale factor" in uuids else 10)
            except asyncio.TimeoutError:  # not the builtin TimeoutError before Python 3.11
                break
            assert isinstance(raw, bytes)
            size, packed = int.from_bytes(raw[:8], "little"), int.from_bytes(raw[8:16], "little")
            inner = zstandard.ZstdDecompressor().decompress(raw[16 : 16 + packed], size)
            for m in msgspec.msgpack.decode(inner)["messages"]:
                if "label" in m.get("props", {}):
                    uuids[m["props"]["label"]] = m["uuid"]
        z, one = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0)
        camera = _messages.ViewerCameraMessage(one, (1, 1, 1), 1.0, 0.01, 9.0, 48, 64, z, z)
        await ws.send(msgspec.msgpack.encode(camera.as_serializable_dict()))
        with contextlib.suppress(websockets_exceptions.ConnectionClosed):
            await ws.send(build(uuids))
            await asyncio.sleep(0.3)


def update(label: str, value: Any) -> Callable[[dict[str, str]], bytes]:
    import msgspec
    from viser import _messages

    def build(uuids: dict[str, str]) -> bytes:
        message = _messages.GuiUpdateMessage(uuids[label], {"value": value})
        return msgspec.msgpack.encode(message.as_serializable_dict())

    return build


def unknown_message(_: dict[str, str]) -> bytes:
    import msgspec

    return msgspec.msgpack.encode({"type": "NoSuchMessage"})


@pytest.mark.parametrize(
    ("build", "said"),
    [
        (lambda _: b"garbage", "dropped a connection: connection handler failed: DecodeError"),
        (unknown_message, "dropped a connection: connection handler failed: KeyError"),
        (update("Radius", "abc"), "ignored a message: ValueError"),
        (update("Radius", [1, 2]), "ignored a message: TypeError"),
        (update("Fit spheres", [1, 2]), None),  # text that is no number: left alone
        (update("Scale factor", "abc"), None),  # a text field: left as typed
        (update("Radius", 13.0), None),  # past the slider: from its number box, refused
        (update("Center x (m)", "abc"), None),  # not a number: left as typed
        (update("Sphere", "not a number"), None),  # not an option: ignored
        (update("Link", "no_such_link"), None),
        (update("Meshes", "no_such_kind"), None),
    ],
)
def test_a_malformed_message_is_one_line_and_changes_nothing(
    served: tuple[Any, list[str]],
    capfd: pytest.CaptureFixture[str],
    build: Callable[[dict[str, str]], bytes],
    said: str | None,
) -> None:
    """viser and websockets printed a traceback for each (and a dropdown value that is not
    an option reached the page's code, which failed on it)."""
    page, heard = served
    before, document = len(heard), page.state.xrdf
    send(page.url, build)
    time.sleep(0.3)
    err = capfd.readouterr().err
    assert "Traceback" not in err and "Task failed" not in err, err
    new = heard[before:]
    if said is None:
        assert new == []
    else:
        assert len(new) == 1 and said in new[0] and "\n" not in new[0], new
    assert page.state.xrdf == document
    assert page.panels.spheres.link.value in page.robot.frame_names


# --- saving ------------------------------------------------------------------------------------
def test_confirm_saves_only_what_the_review_showed(tmp_path: Path) -> None:
    """Confirm pressed without a review (a client can press a hidden button), after another
    edit, or after another program wrote the file: nothing is written, the review is shown
    again. Before, Confirm wrote whatever the document held then, over whatever was there."""
    from xrdf_tools.edit.page import EditorPage

    target = tmp_path / "panda.xrdf"
    shutil.copy(PANDA_XRDF, target)
    page = EditorPage(
        load_robot(robot_urdf("panda")),
        EditState.start(load_xrdf(target)),
        target=target,
        port=free_port(),
    )
    try:
        panels = page.panels
        assert page.apply(SetRadius("panda_link4", 0, 0.05))
        panels._confirm()
        assert page.message.startswith("not saved: press Save… first")
        panels.review()
        assert page.apply(SetRadius("panda_link4", 0, 0.06))  # an edit after the review
        panels._confirm()
        assert page.message.startswith("not saved: the document or the file changed")
        assert "0.06" in panels.diff.content and target.read_bytes() == PANDA_XRDF.read_bytes()
        target.write_bytes(PANDA_XRDF.read_bytes() + b"# by hand\n")  # another program
        panels._confirm()
        assert page.message.startswith("not saved: the document or the file changed")
        assert "changed on disk since the page read it" in panels.diff.content
        assert target.read_bytes().endswith(b"# by hand\n")
        panels._confirm()  # the user saw the warning, and confirms
        assert page.message == f"saved {target}" and not page.state.dirty
        radius = load_xrdf(target).resolved_spheres("panda_spheres")["panda_link4"][0].radius
        assert radius == 0.06
    finally:
        page.close()


def test_a_save_that_cannot_be_written_loses_nothing_and_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A read-only target, a full disk, a symlink: the file as it was (or written through the
    link), one line on the page and for the terminal, no temporary file left."""
    import errno

    real = tmp_path / "real.xrdf"
    shutil.copy(PANDA_XRDF, real)
    target = tmp_path / "panda.xrdf"
    target.symlink_to(real.name)
    page, heard = _panda_editor(target)
    try:
        assert page.apply(SetRadius("panda_link4", 0, 0.05))
        real.chmod(0o444)  # the user protected the file
        page.panels.review()
        why = f"{target}: is read-only (no write permission): refusing to replace it"
        assert page.panels.diff.content.startswith("**Cannot save**: ")
        assert not page.panels.confirm.visible
        assert not page.save() and page.message.startswith(f"not saved: {why}")
        assert heard[-1] == page.message
        real.chmod(0o644)

        def full(*_: object) -> None:
            raise OSError(errno.ENOSPC, "No space left on device")

        monkeypatch.setattr(os, "replace", full)
        assert not page.save()
        assert page.message == f"not saved: {target}: cannot write: No space left on device"
        assert heard[-1] == page.message and page.state.dirty
        monkeypatch.undo()
        assert real.read_bytes() == PANDA_XRDF.read_bytes()
        assert sorted(p.name for p in tmp_path.iterdir()) == ["panda.xrdf", "real.xrdf"]
        assert page.save() and target.is_symlink()  # written through the link, kept
        assert load_xrdf(real).resolved_spheres("panda_spheres")["panda_link4"][0].radius == 0.05
    finally:
        page.close()


# --- numbers typed -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "value"),
    [("1e-3", 0.001), ("0.001", 0.001), (" -2 ", -2.0), (".5", 0.5), ("1.", 1.0), ("5E+2", 500.0)],
)
def test_a_typed_number_may_have_an_exponent(text: str, value: float) -> None:
    assert parse_typed(text) == value


@pytest.mark.parametrize("text", ["", "-", "1e", "1e-", "nan", "inf", "1_000", "0x10", "1,5"])
def test_what_is_not_a_number_yet_is_left_alone(text: str) -> None:
    assert parse_typed(text) is None


def test_a_typed_field_is_not_rewritten_while_it_reads_as_the_document() -> None:
    """The page shows the document's value after each edit: rewriting ``1.`` as ``1.0``
    while the user types ``1.5`` would make it ``1.05``."""

    class Gui:
        def add_text(self, label: str, value: str, hint: str | None = None) -> Any:
            return type("Box", (), {"value": value})()

    field = TypedNumber(Gui(), "Buffer (m)", 0.0, lo=0.0, hi=0.5, unit=" m")
    assert field.box.value == "0.0"
    for typed in ("1.", "1e-3", "0.0010"):
        field.box.value = typed
        field.show(parse_typed(typed))  # type: ignore[arg-type]
        assert field.box.value == typed
    field.show(0.25)
    assert field.box.value == "0.25"
    assert field.refusal(0.6) == "not set: Buffer (m) takes 0 to 0.5 m, not 0.6"
    assert field.refusal(0.5) is None
    # the edit of "5" under way when the browser has sent "5e" (on its way to 5e-3): the
    # page shows the document after the edit, and must leave the text alone
    callbacks: list[Any] = []
    field.box.on_update = callbacks.append
    done: list[float] = []

    def act(value: float) -> None:
        field.box.value = "5e"  # the next keystroke arrived meanwhile
        field.show(value)
        done.append(value)

    field.on_number(done.append, act)
    field.box.value = "5"
    callbacks[0](type("Event", (), {"client": object(), "target": field.box})())
    assert field.box.value == "5" and done == ["not set: Buffer (m) takes 0 to 0.5 m, not 5"]
    field.hi = None
    field.box.value = "5"
    callbacks[0](type("Event", (), {"client": object(), "target": field.box})())
    assert field.box.value == "5e" and done[-1] == 5.0


def test_deleting_the_last_sphere_of_a_link_with_geometry_says_a_planner_cannot_see_it(
    served: tuple[Any, list[str]],
) -> None:
    from xrdf_tools.edit import DeleteSphere

    page, _ = served
    spheres = page.panels.spheres
    n = len(page.state.xrdf.resolved_spheres(page.state.group)["panda_link7"])
    for left in range(n - 1, -1, -1):
        page.pick("panda_link7", 0)
        spheres._on_sphere(DeleteSphere)
        assert ("a planner cannot see it" in page.message) == (left == 0), page.message
    assert page.message.endswith(
        "warning: 'panda_link7' has collision geometry and no spheres now: a planner cannot "
        "see it (xrdf lint: mesh-without-spheres)"
    )
    for _ in range(n):
        page.undo()
    assert not page.state.dirty


def browser_event(target: Any) -> Any:
    """An update event as the browser's page sends it."""
    return type("Event", (), {"client": object(), "target": target})()


def typed_in(field: Any, text: str) -> None:
    """``text`` arrives in ``field`` from the browser (its callbacks run as viser runs them)."""
    field.box.value = text
    for callback in field.box._impl.update_cb:
        callback(browser_event(field.box))


def test_every_number_is_typed_as_the_lengths_are(served: tuple[Any, list[str]]) -> None:
    """Counts, factors and the radius read what was typed, exponent and all; a fraction in a
    count or a value past a field's range is refused with a message, the text left as typed
    (viser's number fields dropped the exponent: 1e-3 typed for the radius made it 13 m, and
    a count past its range was taken at the end of it)."""
    page, _ = served
    spheres, mask, panels = page.panels.spheres, page.panels.mask, page.panels
    page.pick("panda_link4", 0)
    link4 = page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"]
    # the radius typed: 1e-3 is 1 mm, one undo step with what was typed before it
    assert spheres.typed_radius.box.value == repr(link4[0].radius)
    for typed in ("1", "1e", "1e-", "1e-3"):
        typed_in(spheres.typed_radius, typed)
    assert page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"][0].radius == 0.001
    page.undo()
    assert page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"] == link4
    # the slider's number box sends 13 for "1e-3" (should its box be shown): refused
    spheres.radius.value = 13.0
    spheres._dragged_radius()
    assert page.message == (
        "not set: the Radius slider takes 0.0005 to 0.3 m, not 13 (type the radius in Radius (m))"
    )
    assert page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"] == link4
    # counts: an exponent is read, a fraction or a value past the range refused, as typed
    mask.samples.box.value = "1e5"
    assert mask.samples.take(page.say) == 100_000
    typed_in(mask.samples, "2e6")  # said as it is typed, and when the report would run
    assert page.message == "not set: Report samples takes 1 to 1,000,000, not 2,000,000"
    page.say("")
    assert mask.samples.take(page.say) is None and mask.samples.box.value == "2e6"
    assert page.message == "not set: Report samples takes 1 to 1,000,000, not 2,000,000"
    panels.fit_count.box.value = "2.5"
    panels._fit()
    assert page.message == "not set: Fit spheres takes a whole number, not 2.5"
    assert panels.proposal is None
    spheres.between.box.value = "-"
    spheres._connect()
    assert page.message == "not set: type a number in Spheres between"
    spheres.factor.box.value = "20"
    spheres._scale()
    assert page.message == "not set: Scale factor takes 0.1 to 10, not 20"
    assert page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"] == link4
    # a joint's slider box sends what is typed there: a value past the joint's limits is
    # not posed (99 typed posed the joint at 99 rad)
    q = page.q.copy()
    slider = panels.sliders[1]
    slider.value = 99.0
    panels._slider_moved(int(page.robot.cspace_index[1]), slider)(browser_event(slider))
    assert page.message == (
        "not posed: panda_joint2 moves within its limits, -1.7628 to 1.7628, not 99"
    )
    assert (page.q == q).all()
    assert not page.state.dirty
