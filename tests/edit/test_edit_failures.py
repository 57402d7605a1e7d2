"""``xrdf edit`` when things go wrong: an address it cannot listen on, a save that cannot be
written, a file changed under the page, a document changed after its review. Each failure is
one line (in the page and on the terminal), and nothing the user had is lost.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.browser import free_port
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.edit.guard import check_address
from xrdf_tools.util.errors import InputError

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
#: An address of no machine here (TEST-NET-1, RFC 5737).
ELSEWHERE = "192.0.2.1"

pytest.importorskip("viser", reason="xrdf edit needs viser (the edit extra)")


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
