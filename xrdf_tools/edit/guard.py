"""Who may talk to the editor's server: the page it serves, at one of its own addresses.

Any web page open in the user's browser can open a websocket to ``127.0.0.1``; the editor's
page is a websocket client like any other, so such a page could read the GUI and press its
buttons -- delete spheres, then Save. And a page at ``evil.example`` whose name is then made
to resolve to ``127.0.0.1`` (DNS rebinding) reaches the server as its own origin.

Browsers send ``Origin`` on every websocket handshake and set ``Host`` from the address they
connect to; a page's scripts can set neither. So every request (the page's files and the
websocket) is checked here before viser sees it:

- ``Host`` must name one of the server's own addresses: ``127.0.0.1``, ``localhost``,
  ``::1``, the ``--host`` it listens on, the address the connection arrived at (and, listening
  on every interface, this machine's name). Its port is not checked, so an SSH tunnel to
  another local port still works.
- ``Origin``, when sent, must be ``http://`` one of those addresses at the port of ``Host``:
  the page the browser shows was served by this server.

A request without ``Origin`` comes from a program, not from a web page; programs on this
machine can reach the port anyway (see docs/security.md).
"""

from __future__ import annotations

import asyncio
import http
import ipaddress
import logging
import re
import socket
import threading
from collections.abc import Callable, Collection, Sequence
from typing import TYPE_CHECKING, Any, TypeVar

from ..util.errors import InputError, MissingDependencyError, shown_text

if TYPE_CHECKING:
    from websockets.asyncio.server import ServerConnection
    from websockets.http11 import Request, Response

__all__ = ["RequestGuard", "check_address", "own_names", "refusal", "start_guarded"]

T = TypeVar("T")

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1")
WILDCARD_HOSTS = ("", "0.0.0.0", "::")

#: ``name[:port]`` or ``[v6][:port]``: a Host header, or an Origin after its ``http://``.
_HOST = re.compile(
    r"(?:\[(?P<v6>[0-9A-Fa-f:.]+)\]|(?P<name>[A-Za-z0-9._-]+))(?::(?P<port>[0-9]{1,5}))?"
)
#: Distinct refusals reported (a page retrying cannot flood the terminal).
MAX_REPORTED = 32


def check_address(host: str) -> None:
    """Raise :class:`InputError` (one line) when no server can listen on ``host``: a name that
    does not resolve, an address of another machine. viser tries the next port on any such
    error, a thousand times, and then waits for a server that never started: the command
    hung instead of saying why."""
    try:
        infos = socket.getaddrinfo(
            host or None, 0, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE
        )
    except (OSError, UnicodeError) as e:
        reason = getattr(e, "strerror", None) or str(e)
        raise InputError(f"cannot serve on {shown_text(host)}: {reason}") from None
    family, kind, proto, _, address = infos[0]
    try:
        with socket.socket(family, kind, proto) as probe:
            probe.bind(address)
    except OSError as e:
        reason = e.strerror or str(e)
        raise InputError(
            f"cannot serve on {shown_text(host)}: {reason} (not an address of this machine?)"
        ) from None


def own_names(bind_host: str) -> frozenset[str]:
    """The names a browser may use for a server listening on ``bind_host`` (lower case):
    the loopback names, ``bind_host`` itself, and this machine's name when it listens on every
    interface. The address a connection arrives at is added per connection."""
    names = set(LOOPBACK_NAMES)
    host = bind_host.strip("[]").lower()
    if host in WILDCARD_HOSTS:
        names.add(_canonical(socket.gethostname()))
    else:
        names.add(_canonical(host))
    return frozenset(names)


def _canonical(name: str) -> str:
    """``name`` as compared: lower case, without the trailing dot of a fully qualified name
    (``localhost.``), an IP address in its short form (an IPv4-mapped one as IPv4)."""
    name = name.lower().removesuffix(".")
    try:
        ip = ipaddress.ip_address(name)
    except ValueError:
        return name
    mapped = ip.ipv4_mapped if isinstance(ip, ipaddress.IPv6Address) else None
    return str(mapped or ip)


def _host_port(text: str) -> tuple[str, int | None] | None:
    """``(name, port)`` of ``name[:port]``, the name in lower case; None when malformed."""
    m = _HOST.fullmatch(text)
    if m is None:
        return None
    port = int(m["port"]) if m["port"] else None
    if port is not None and port > 65535:
        return None
    if m["v6"] is not None:
        try:
            ipaddress.IPv6Address(m["v6"])
        except ValueError:
            return None
    return _canonical(m["v6"] or m["name"]), port


def refusal(hosts: Sequence[str], origins: Sequence[str], names: Collection[str]) -> str | None:
    """Why a request with these ``Host`` and ``Origin`` headers is refused (one line), or
    None when it may go through. ``names``: the server's own addresses (:func:`own_names`)."""
    if len(hosts) != 1 or (host := _host_port(hosts[0])) is None:
        return "refused a request without one valid Host header"
    if host[0] not in names:
        return (
            f"refused a request for {shown_text(hosts[0])}: not an address of this editor "
            f"(a page whose name now resolves here?); open it at one of {', '.join(sorted(names))}"
        )
    if not origins:
        return None
    origin = origins[0] if len(origins) == 1 else ""
    own = _host_port(origin[len("http://") :]) if origin.lower().startswith("http://") else None
    if own is None or own[0] not in names or (own[1] or 80) != (host[1] or 80):
        page = shown_text(origin) if len(origins) == 1 else f"{len(origins)} origins"
        return (
            f"refused a connection from a page at {page}: only the editor's own page may drive it"
        )
    return None


class RequestGuard:
    """The check every request to the editor's server passes first (a websockets
    ``process_request``). ``on_refused`` hears each distinct refusal once."""

    def __init__(self, bind_host: str, on_refused: Callable[[str], None] | None = None) -> None:
        self.names = own_names(bind_host)
        self.on_refused = on_refused
        self._reported: set[str] = set()
        self._lock = threading.Lock()

    def check(self, connection: ServerConnection, request: Request) -> Response | None:
        """A 403 response for a request that is refused, None for one that may go on."""
        names = self.names | _arrived_at(connection)
        why = refusal(request.headers.get_all("Host"), request.headers.get_all("Origin"), names)
        if why is None:
            return None
        self._report(why)
        return connection.respond(http.HTTPStatus.FORBIDDEN, f"xrdf edit: {why}\n")

    def wrap(self, inner: Callable[..., Any] | None) -> Callable[..., Any]:
        """``inner`` (viser's own ``process_request``: it serves the page's files) behind
        :meth:`check`."""

        def process_request(connection: ServerConnection, request: Request) -> Any:
            refused = self.check(connection, request)
            if refused is not None or inner is None:
                return refused
            return inner(connection, request)

        return process_request

    def log_to_report(self) -> logging.Logger:
        """A logger for the websockets server that reports each error it logs as one line
        (a malformed request or message: websockets logged a traceback)."""
        logger = logging.Logger("xrdf_tools.edit.server", logging.WARNING)  # not registered
        logger.addHandler(_OneLine(self._report))
        return logger

    def loop_error(self, _loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        """The server's event loop exception handler: a message viser could not take (a
        value of the wrong type for a control, an unknown message) is one line, not the
        traceback asyncio prints."""
        self._report(f"the editor's server ignored a message: {_error_text(context)}")

    def _report(self, why: str) -> None:
        with self._lock:
            if why in self._reported or len(self._reported) >= MAX_REPORTED:
                return
            self._reported.add(why)
        if self.on_refused is not None:
            self.on_refused(why)


class _OneLine(logging.Handler):
    """Each record as one line (its message and its exception, no traceback) to ``report``."""

    def __init__(self, report: Callable[[str], None]) -> None:
        super().__init__(logging.WARNING)
        self.report = report

    def emit(self, record: logging.LogRecord) -> None:
        exc = record.exc_info[1] if record.exc_info else None
        text = record.getMessage() + (f": {_exception_text(exc)}" if exc is not None else "")
        self.report(f"the editor's server dropped a connection: {shown_text(text, 200)}")


def _error_text(context: dict[str, Any]) -> str:
    exc = context.get("exception")
    return _exception_text(exc) if exc is not None else str(context.get("message", "error"))


def _exception_text(exc: BaseException) -> str:
    return shown_text(f"{type(exc).__name__}: {exc}", 200)


def _arrived_at(connection: ServerConnection) -> frozenset[str]:
    """The address the connection arrived at (an IPv4 one as such, not IPv6-mapped): a
    browser that reached the server by that address names it in Host."""
    local = connection.local_address
    if not local:
        return frozenset()
    try:
        ip = ipaddress.ip_address(str(local[0]).split("%")[0])
    except ValueError:
        return frozenset()
    return frozenset({_canonical(str(ip))})


_PATCHING = threading.Lock()


def start_guarded(make: Callable[[], T], guard: RequestGuard, close: Callable[[T], None]) -> T:
    """``make()`` -- a viser server -- with ``guard`` in front of every request it serves.

    viser 1.1 has no option for this. It starts its server inside ``ViserServer()`` by calling
    ``websockets.asyncio.server.serve(..., process_request=...)`` from its own thread, and the
    constructor returns once the port is bound. So while ``make()`` runs, that ``serve`` is
    replaced by one that puts the guard before viser's ``process_request``. If viser did not
    call it (a viser that serves another way), the server is closed with ``close`` and
    MissingDependencyError is raised: the page is never served unguarded.
    """
    import websockets.asyncio.server as ws_server

    original = ws_server.serve
    guarded = 0

    def serve(*args: Any, process_request: Any = None, **kwargs: Any) -> Any:
        nonlocal guarded
        guarded += 1
        kwargs["logger"] = guard.log_to_report()
        return original(*args, process_request=guard.wrap(process_request), **kwargs)

    with _PATCHING:
        setattr(ws_server, "serve", serve)  # noqa: B010 (mypy: a function for a class)
        try:
            made = make()
        finally:
            setattr(ws_server, "serve", original)  # noqa: B010
    if not guarded:
        close(made)
        raise MissingDependencyError(
            "xrdf edit cannot keep other web pages from driving its page with this viser "
            "(it did not serve through websockets.asyncio.server.serve): "
            'pip install "xrdf-tools[edit]" installs the viser it works with'
        )
    return made
