"""Files a xacro opens itself (``<xacro:include>``, ``xacro.load_yaml``) go through the input
guards: a FIFO is refused before it is opened (opening one blocks until a writer comes), a
directory is said to be one; the messages that are then placed read no file unguarded."""

from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from xrdf_tools.robot.xacro_source import expand_xacro
from xrdf_tools.util.errors import SourceError

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")

HEAD = '<?xml version="1.0"?>\n<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'


@contextlib.contextmanager
def _fifo(path: Path) -> Iterator[Path]:
    """A FIFO at ``path`` whose every opening for reading is soon released: a writer opens it,
    writes a line of garbage and closes it, again and again, so that a reader that should never
    have opened it fails the test instead of blocking it for ever."""
    os.mkfifo(path)
    stop = threading.Event()

    def writer() -> None:
        while not stop.is_set():
            with contextlib.suppress(OSError), open(path, "w") as fh:  # blocks until a reader
                fh.write("not xml\n")

    thread = threading.Thread(target=writer, daemon=True)
    thread.start()
    try:
        yield path
    finally:
        stop.set()
        # release the writer's open: a reader that does not block
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
        thread.join(timeout=5)
        os.close(fd)


@pytest.mark.parametrize(
    "use",
    [
        '<xacro:include filename="pipe.xacro"/>',
        '<xacro:property name="y" value="${xacro.load_yaml(\'pipe.xacro\')}"/><link name="l${y}"/>',
    ],
    ids=["include", "load_yaml"],
)
def test_a_fifo_a_xacro_opens_is_refused_unopened(tmp_path: Path, use: str) -> None:
    top = tmp_path / "arm.urdf.xacro"
    top.write_text(f'{HEAD}  <link name="base_link"/>\n  {use}\n</robot>\n')
    with _fifo(tmp_path / "pipe.xacro"), pytest.raises(SourceError) as exc:
        expand_xacro(top)
    assert "is a FIFO (named pipe), not a regular file" in str(exc.value)
    assert "pipe.xacro" in str(exc.value)


def test_an_included_directory_is_said_to_be_one(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    top = tmp_path / "arm.urdf.xacro"
    top.write_text(f'{HEAD}  <xacro:include filename="parts"/>\n</robot>\n')
    with pytest.raises(SourceError, match="is a directory"):
        expand_xacro(top)


def test_a_file_read_again_to_place_a_message_is_guarded(tmp_path: Path) -> None:
    """The xacro error's position is searched in every file the expansion opened: a FIFO
    among them is skipped, not read (nor waited for)."""
    from xrdf_tools.util.fileio import reread_text

    text = tmp_path / "a.xacro"
    text.write_bytes(b"caf\xc3\xa9 \xff")
    assert reread_text(text) is None  # not UTF-8
    assert reread_text(text, errors="replace") == "café \ufffd"
    assert reread_text(tmp_path / "gone.xacro") is None
    with _fifo(tmp_path / "pipe.xacro") as pipe:
        assert reread_text(pipe) is None
