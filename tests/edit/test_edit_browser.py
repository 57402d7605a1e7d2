"""``xrdf edit`` in a real browser: headless Chromium (the system's ``chromium``) driven by
Playwright, on the example-robot-data Panda with fixtures/panda/panda.xrdf.

The page is served in this process (a viser server runs in its own threads), so the test can
compare what the browser shows with the page's state and the library's answers. One scenario
walks through the editor as a user would: pose until a known pair collides, move and resize a
sphere, undo/redo, refit a link, toggle a mask pair, take a joint into the c-space, save, and
compare the file with the expected change via the semantic diff.

Screenshots go to ``$XRDF_EDIT_SCREENSHOTS`` when set (docs/images for docs/edit.md), else to
the test's temporary directory. Skipped only when Playwright or chromium is missing.
"""

from __future__ import annotations

import os
import re
import shutil
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.browser import CHROMIUM, CHROMIUM_ARGS, free_port
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.diff import diff_files, diff_xrdf
from xrdf_tools.edit import (
    EditRobot,
    EditState,
    MoveSphere,
    ReplaceSpheres,
    SetCspace,
    SetIgnored,
    SetRadius,
    save,
)
from xrdf_tools.edit.view import CHECKED_RGB
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import load_xrdf

pytest.importorskip("viser", reason="xrdf edit needs viser (the edit extra)")
sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
TIMEOUT_MS = 60_000
sync_api.expect.set_options(timeout=TIMEOUT_MS)

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not Path(CHROMIUM).is_file(), reason=f"no chromium at {CHROMIUM}"),
]


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    with sync_api.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


def shots_dir(tmp_path: Path) -> Path:
    d = Path(os.environ.get("XRDF_EDIT_SCREENSHOTS") or tmp_path)
    d.mkdir(parents=True, exist_ok=True)
    return d


# --- driving viser's controls by their labels --------------------------------------------------
def row(page: Any, label: str) -> Any:
    """The GUI row of the control labelled ``label``."""
    lab = page.locator("label").filter(has_text=re.compile(f"^{re.escape(label)}$")).first
    return lab.locator("xpath=ancestor::p/parent::div/parent::div")


def set_number(page: Any, label: str, value: float, nth: int = 0) -> None:
    box = row(page, label).locator("input.mantine-NumberInput-input").nth(nth)
    box.fill(str(value))
    box.press("Enter")


def type_text(page: Any, label: str, text: str) -> None:
    """Type ``text`` key by key in the text field labelled ``label`` (the page's lengths and
    limits), as a user does: the browser sends each keystroke."""
    box = row(page, label).locator("input").first
    box.click()
    box.press("Control+a")
    box.press_sequentially(text)


def choose(page: Any, label: str, option: str) -> None:
    page.get_by_role("combobox", name=label, exact=True).click()
    page.get_by_role("option", name=option, exact=True).click()


def settle(editor: Any, page: Any) -> None:
    """Let the page finish what the last edit started (the server redraws under its lock,
    then the browser receives the new controls) before clicking a control it may rebuild."""
    with editor.lock:
        pass
    page.wait_for_timeout(500)


def wait_for(condition: Any, what: str, timeout: float = 60.0) -> None:
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.05)


# --- the scenario ----------------------------------------------------------------------------
def _locked(editor: Any, name: str) -> Any:
    """An attribute of the page read under its lock: not between a pose and its collisions."""
    with editor.lock:
        return getattr(editor, name)


@contextmanager
def panda_page(browser: Any, target: Path, **options: Any) -> Iterator[tuple[Any, Any]]:
    """The editor on a copy of the bundled Panda XRDF at ``target`` (``options``: the
    page's, e.g. ``readonly``), and a browser tab on it; both closed after."""
    from xrdf_tools.edit.page import EditorPage

    shutil.copy(PANDA_XRDF, target)
    robot = load_robot(robot_urdf("panda"))
    editor = EditorPage(
        robot, EditState.start(load_xrdf(target)), target=target, port=free_port(), **options
    )
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 900})
        page.set_default_timeout(TIMEOUT_MS)
        page.goto(editor.url)
        yield editor, page
        page.close()
    finally:
        editor.close()


def test_edit_in_the_browser(browser: Any, tmp_path: Path) -> None:
    expect = sync_api.expect
    robot = load_robot(robot_urdf("panda"))
    original = load_xrdf(PANDA_XRDF)
    target = tmp_path / "panda.xrdf"
    shots = shots_dir(tmp_path)
    t0 = time.perf_counter()
    with panda_page(browser, target) as (editor, page):
        expect(page.get_by_text("Default pose")).to_be_visible()
        print(f"page up in {time.perf_counter() - t0:.2f} s")
        # the software-rendering notice of a GPU-less browser would cover the screenshots
        page.add_style_tag(content=".mantine-Notification-root { display: none !important; }")

        # 1. raise panda_joint2 until a pair the mask checks collides: the library finds the
        #    value on a 0.1 rad grid, the slider goes there in two steps
        reference = EditRobot(robot, original)
        q = reference.default_pose(original)
        hit = None
        for k in range(18):
            q[1] = round(0.1 * k, 2)
            if reference.collisions(original, q).checked:
                hit = q[1]
                break
        assert hit is not None, "raising panda_joint2 never made a checked pair collide"
        colliding = page.get_by_text("COLLIDING").first
        for value in (round(hit - 0.1, 2), hit):
            set_number(page, "panda_joint2", value)
            wait_for(lambda v=value: abs(_locked(editor, "q")[1] - v) < 1e-9, "the pose")
            # the page sets the pose and then its collisions, both under its lock
            assert bool(_locked(editor, "collisions").checked) == (value == hit)
        want = reference.collisions(original, editor.q)
        expect(colliding).to_be_visible()
        first = want.checked[0]
        text = page.get_by_text(re.compile(r"\d+ colliding, \d+ ignored")).locator("..")
        expect(text).to_contain_text(f"{first.frame_a} ↔ {first.frame_b}")
        assert CHECKED_RGB in editor.view.colors[first.frame_a]
        page.screenshot(path=str(shots / "edit_collision.png"))

        # 2. move and resize a sphere of panda_link5; undo and redo the resize
        choose(page, "Link", "panda_link5")
        choose(page, "Sphere", "0")
        wait_for(lambda: editor.selected == ("panda_link5", 0), "the selection")

        def link5_first() -> Any:
            return editor.state.xrdf.resolved_spheres("panda_spheres")["panda_link5"][0]

        for i, (axis, v) in enumerate(zip("xyz", (0.01, 0.02, 0.03), strict=True)):
            type_text(page, f"Center {axis} (m)", f"{v * 1000:g}e-3")  # one field at a time:
            wait_for(lambda i=i, v=v: link5_first().center[i] == v, f"centre {axis}")  # each
            settle(editor, page)
        type_text(page, "Radius (m)", "7e-2")

        wait_for(lambda: link5_first().radius == 0.07, "the radius")
        wait_for(lambda: link5_first().center == (0.01, 0.02, 0.03), f"the move ({link5_first()})")
        radius_before = original.resolved_spheres("panda_spheres")["panda_link5"][0].radius
        page.get_by_role("button", name="Undo").click()
        wait_for(lambda: link5_first().radius == radius_before, "undo")
        page.get_by_role("button", name="Redo").click()
        wait_for(lambda: link5_first().radius == 0.07, "redo")

        # 3. refit panda_link3 with 3 spheres, look at the metrics, accept
        settle(editor, page)
        choose(page, "Link", "panda_link3")
        type_text(page, "Fit spheres", "3")
        # the click must reach the server after the link and the count (as in step 5)
        wait_for(
            lambda: (
                (editor.selected or ("",))[0] == "panda_link3"
                and editor.panels.fit_count.read() == 3
            ),
            "the link and count to fit",
        )
        settle(editor, page)
        page.get_by_role("button", name="Fit link").click()
        expect(page.get_by_role("button", name="Accept fit")).to_be_visible(timeout=120_000)
        expect(page.get_by_text("protrusion p95")).to_be_visible()
        proposal = editor.panels.proposal
        assert proposal is not None and len(proposal.spheres) == 3
        expect(page.get_by_text(f"{proposal.after.coverage:.1%}").first).to_be_visible()
        page.get_by_role("button", name="Discard fit").scroll_into_view_if_needed()
        page.screenshot(path=str(shots / "edit_refit.png"))
        page.get_by_role("button", name="Accept fit").click()
        wait_for(
            lambda: len(editor.state.xrdf.resolved_spheres("panda_spheres")["panda_link3"]) == 3,
            "the refit",
        )

        # 4. ignore the colliding pair with its toggle
        label = f"{first.frame_a} ↔ {first.frame_b}"

        def ignored() -> bool:
            sc = editor.state.xrdf.self_collision
            return sc is not None and sc.is_ignored(first.frame_a, first.frame_b)

        settle(editor, page)
        page.get_by_label(label, exact=True).click()
        wait_for(ignored, "the mask toggle")

        # 5. take the finger joint into the c-space: the Pose panel gets its slider
        settle(editor, page)
        page.get_by_text("C-space", exact=True).click()  # the folder starts closed
        choose(page, "Joint", "panda_finger_joint1")
        # the tick must reach the server after the choice (else it toggles the joint shown
        # before, panda_joint1, out of the c-space): wait for the server to have the choice
        wait_for(
            lambda: editor.panels.cspace.joint.value == "panda_finger_joint1", "the joint choice"
        )
        settle(editor, page)
        page.get_by_label("In c-space", exact=True).click()

        def finger_in() -> bool:
            cs = editor.state.xrdf.cspace
            return cs is not None and "panda_finger_joint1" in cs.joint_names

        wait_for(finger_in, "the c-space edit")
        slider = row(page, "panda_finger_joint1").locator("input.mantine-NumberInput-input")
        expect(slider).to_have_value("0.04")  # the finger's default position
        page.get_by_text("In c-space", exact=True).scroll_into_view_if_needed()
        page.screenshot(path=str(shots / "edit_cspace.png"))

        # 6. save: the diff first, then the file
        assert target.read_bytes() == PANDA_XRDF.read_bytes()  # nothing written yet
        page.get_by_role("button", name="Save…").click()
        expect(page.get_by_text("geometry", exact=False).first).to_be_visible()
        page.get_by_role("button", name="Confirm save").scroll_into_view_if_needed()
        page.screenshot(path=str(shots / "edit_save.png"))
        page.get_by_role("button", name="Confirm save").click()
        wait_for(lambda: not editor.state.dirty, "the save")

        expected = EditState.start(original)
        for edit in (
            MoveSphere("panda_link5", 0, (0.01, 0.02, 0.03)),
            SetRadius("panda_link5", 0, 0.07),
            ReplaceSpheres("panda_link3", proposal.spheres),
            SetIgnored(first.frame_a, first.frame_b, True),
        ):
            expected = expected.apply(edit)
        finger = reference.cspace_with(
            expected.xrdf, "panda_finger_joint1", included=True, acceleration=10.0, jerk=1000.0
        )
        expected = expected.apply(SetCspace(finger))
        expected_path = tmp_path / "expected.xrdf"
        save(expected, expected_path)
        assert diff_files(expected_path, target).is_equal
        assert not diff_xrdf(original, load_xrdf(target)).is_equal


def test_readonly_page_does_not_save(browser: Any, tmp_path: Path) -> None:
    expect = sync_api.expect
    target = tmp_path / "panda.xrdf"
    with panda_page(browser, target, readonly=True) as (editor, page):
        expect(page.get_by_role("button", name="Save…")).to_be_disabled()
        expect(page.get_by_text("read-only")).to_be_visible()
        choose(page, "Link", "panda_link2")
        settle(editor, page)
        choose(page, "Sphere", "0")
        settle(editor, page)
        type_text(page, "Radius (m)", "0.08")
        wait_for(lambda: editor.state.dirty, "the edit")
        assert not editor.save()
        assert target.read_bytes() == PANDA_XRDF.read_bytes()


def test_typed_values_the_document_cannot_take(browser: Any, tmp_path: Path) -> None:
    """Numbers typed key by key, with an exponent or past a field's bounds: a length is the
    number typed (``5e-3`` is 5 mm; viser's number field made it 0.5, then 0), one outside
    the field's range is refused and left as typed; nothing the saved file could not hold
    reaches it, and a configuration row past the end is refused; the refusal shows where the
    user types."""
    expect = sync_api.expect
    configs = tmp_path / "q.npy"
    np.save(configs, np.array([[0.0] * 7, [0.1] * 7, [0.2] * 7]))
    target = tmp_path / "panda.xrdf"
    with panda_page(browser, target, configs=configs) as (editor, page):
        expect(page.get_by_text("Default pose")).to_be_visible()
        choose(page, "Link", "panda_link3")
        settle(editor, page)
        choose(page, "Sphere", "0")
        settle(editor, page)

        def sphere() -> Any:
            return editor.state.xrdf.resolved_spheres(editor.state.group)["panda_link3"]

        before_spheres = sphere()

        def buffer() -> float:
            sc = editor.state.xrdf.self_collision
            return -1.0 if sc is None else float(sc.buffer_distance.get("panda_link3", 0.0))

        buffer_before = buffer()
        type_text(page, "Buffer (m)", "7")  # the field takes 0 to 0.5 m
        settle(editor, page)
        refusal = "not set: Buffer (m) takes 0 to 0.5 m, not 7"
        wait_for(lambda: editor.message == refusal, "the refusal")
        assert buffer() == buffer_before
        # said where the user types, not only at the top of the Document panel
        toast = page.locator(".mantine-Notification-root").filter(has_text=refusal)
        expect(toast).to_be_visible()
        assert toast.bounding_box()["y"] < 900
        expect(row(page, "Buffer (m)").locator("input").first).to_have_value("7")  # as typed
        type_text(page, "Buffer (m)", "5e-3")  # an exponent: 5 mm (it arrived as 0.5, then 0)
        settle(editor, page)
        wait_for(lambda: buffer() == 0.005, "the buffer typed with an exponent")
        expect(row(page, "Buffer (m)").locator("input").first).to_have_value("5e-3")
        # a centre past twice the robot's reach is refused, the field keeps what was typed
        type_text(page, "Center x (m)", "2000000")
        settle(editor, page)
        wait_for(lambda: "not moved" in editor.message, "the refusal")
        # ... and the centre typed with an exponent is the number typed (it arrived as 1,
        # then 13: the sphere went 1 m away)
        type_text(page, "Center x (m)", "1e-3")
        settle(editor, page)
        wait_for(lambda: sphere()[0].center[0] == 0.001, "the centre typed with an exponent")
        assert sphere()[1:] == before_spheres[1:]
        assert sphere()[0].center[1:] == before_spheres[0].center[1:]
        assert editor.state.undo_label.startswith("move panda_link3[0] to (0.0010, ")
        editor.undo()  # the keystrokes of one field are one step
        assert sphere() == before_spheres
        editor.redo()
        # the radius slider is for dragging: its number box (which drops an exponent) is
        # hidden, the radius is typed in Radius (m)
        expect(row(page, "Radius").locator("input.mantine-NumberInput-input")).to_be_hidden()
        q_before = _locked(editor, "q").copy()
        type_text(page, "Configuration", "99")  # 3 rows: refused, left as typed
        settle(editor, page)
        page.get_by_role("button", name=re.compile("Pose configuration")).click()
        wait_for(lambda: editor.message == "not set: Configuration takes 0 to 2, not 99", "no")
        expect(row(page, "Configuration").locator("input").first).to_have_value("99")
        assert np.array_equal(_locked(editor, "q"), q_before)
        type_text(page, "Configuration", "2")
        settle(editor, page)
        page.get_by_role("button", name=re.compile("Pose configuration")).click()
        wait_for(lambda: np.allclose(editor.q[:7], 0.2), "the last row posed")
        assert editor.save()
        assert load_xrdf(target).self_collision == editor.state.xrdf.self_collision


#: A link name that is HTML inside a code span: written into the page's markdown as it is, the
#: backticks would close the span and the browser would build the image and run its handler.
HOSTILE = 'arm`<img src=x onerror="window.__xrdf_injected=1">`_*link*_'


def test_names_from_the_files_are_shown_as_text_never_as_html(browser: Any, tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from xrdf_tools.cli import app
    from xrdf_tools.edit.page import EditorPage

    expect = sync_api.expect
    name = HOSTILE.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;")
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="base"><collision><geometry><box size=".2 .2 .1"/>'
        f'</geometry></collision></link><link name="{name}"><collision><origin xyz="0 0 .2"/>'
        '<geometry><box size=".06 .06 .3"/></geometry></collision></link>'
        f'<joint name="j1" type="revolute"><parent link="base"/><child link="{name}"/>'
        '<axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>'
    )
    target = tmp_path / "r.xrdf"
    args = ["convert", str(urdf), "--fit-spheres", "--per-link", "1", "-n", "100", "-o"]
    done = CliRunner().invoke(app, [*args, str(target)])
    assert done.exit_code == 0, done.output
    state = EditState.start(load_xrdf(target))
    editor = EditorPage(load_robot(urdf), state, target=target, port=free_port())
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 900})
        page.set_default_timeout(TIMEOUT_MS)
        page.goto(editor.url)
        expect(page.get_by_text("Default pose")).to_be_visible()
        expect(page.get_by_text(HOSTILE, exact=True).first).to_be_attached()
        assert page.locator('img[src="x"]').count() == 0
        assert page.evaluate("window.__xrdf_injected") is None
        page.close()
    finally:
        editor.close()


def test_a_diff_shows_in_the_page_line_by_line_and_literally(browser: Any) -> None:
    """The Save… diff in viser's markdown: one line per line, monospace, names shown as
    written (no HTML from a name reaches the page)."""
    import viser

    from xrdf_tools.edit.markup import pre

    diff = (
        "--- a.xrdf (XRDF 2.0)\n+++ b.xrdf (XRDF 2.0)\ndefault_joint_positions: 1 change\n"
        "  ~ j1 = 0.0 -> 0.5\n"
        "  + x`<img src=x onerror=\"document.title='PWNED'\">`y {1+1} <b>b</b>\n```\nend"
    )
    port = free_port()
    server = viser.ViserServer(host="127.0.0.1", port=port, verbose=False)
    try:
        server.gui.add_markdown(pre(diff))
        page = browser.new_page()
        page.goto(f"http://127.0.0.1:{port}")
        shown = page.locator("pre")
        shown.wait_for(timeout=30_000)
        assert shown.inner_text().rstrip("\n") == diff
        assert page.locator("img[src=x]").count() == 0 and page.locator("pre b").count() == 0
        assert page.title() != "PWNED"
        page.close()
    finally:
        server.stop()


OPEN_WEBSOCKET = """async ([url, protocol]) => await new Promise((done) => {
    const ws = new WebSocket(url, protocol);
    ws.onopen = () => { ws.close(); done("open"); };
    ws.onerror = () => done("refused");
})"""


@contextmanager
def other_site(root: Path) -> Iterator[str]:
    """Another web server on this machine (a dev server, a notebook) serving ``root``."""
    import functools
    import http.server
    import threading

    (root / "index.html").write_text("<p>another site</p>")
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(root))
    handler.log_message = lambda *_: None  # type: ignore[attr-defined]
    server = http.server.ThreadingHTTPServer(("127.0.0.1", free_port()), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def test_another_site_in_the_browser_cannot_reach_the_editor(browser: Any, tmp_path: Path) -> None:
    """A page of another local site opens a websocket to the editor, as the editor's own page
    does: Chromium sends the page's Origin and the editor refuses it; from the editor's page
    the same call opens. (A public site's page, http://evil.example, Chromium itself keeps
    from loopback addresses -- its Local Network Access checks -- other browsers do not.)"""
    import viser

    from xrdf_tools.edit.page import EditorPage

    shutil.copy(PANDA_XRDF, tmp_path / "panda.xrdf")
    heard: list[str] = []
    editor = EditorPage(
        load_robot(robot_urdf("panda")),
        EditState.start(load_xrdf(tmp_path / "panda.xrdf")),
        target=tmp_path / "panda.xrdf",
        port=free_port(),
        on_refused=heard.append,
    )
    ws = [editor.url.replace("http://", "ws://"), f"viser-v{viser.__version__}"]
    try:
        with other_site(tmp_path) as site:
            page = browser.new_page()
            page.goto(site)
            assert page.evaluate(OPEN_WEBSOCKET, ws) == "refused"
            page.goto(editor.url)
            assert page.evaluate(OPEN_WEBSOCKET, ws) == "open"
            page.close()
    finally:
        editor.close()
    assert heard == [
        f"refused a connection from a page at {site}: only the editor's own page may drive it"
    ]
