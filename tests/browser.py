"""What the editor's browser tests and the start-up benchmark share: Debian's chromium, the
flags it runs with here (headless, no sandbox as root, no background network on a closed
machine) and a free local port."""

from __future__ import annotations

import os
import shutil
import socket

CHROMIUM = os.environ.get("XRDF_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])
