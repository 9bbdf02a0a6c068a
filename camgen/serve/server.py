"""The HTTP server of ``camgen serve`` and its routing (stdlib :mod:`http.server`, one thread per
request).  What each endpoint computes is :mod:`camgen.serve.api`; the page is ``page.html``.

Safety (issue 29 item 4), checked in this order for every request:

* bound to 127.0.0.1 by default; another address only with ``allow_remote`` (a warning line:
  the server has no authentication);
* the ``Host`` header must name this server as a browser on this machine does
  (``127.0.0.1:PORT``, ``localhost:PORT``, ``[::1]:PORT``, or the bound address): anything else
  is 403, so a web page whose DNS name is re-pointed to 127.0.0.1 (DNS rebinding) is refused; an
  ``Origin`` header, where a browser sends one, must be this server's own (403: another site's
  page cannot post to it);
* a path outside the served set is 404: exactly ``/``, the ``/api/...`` endpoints and
  ``/files/<token>/<name>`` of a file this server made (:mod:`camgen.serve.files`, sent as an
  attachment in a sandbox: a downloaded report runs no script on this origin); a path holding
  ``..`` (also percent-encoded) or a backslash never reaches a lookup, and nothing is read from disk
  by path (no directory listing);
* a method an endpoint does not take is 405; a POST body must be ``application/json`` (else 415),
  of a stated length (else 411) of at most :data:`MAX_BODY` bytes (else 413, the body unread), and
  a JSON object (else 400).
Nothing is written to disk: the files made for download stay in memory.
"""
from __future__ import annotations

import errno
import ipaddress
import json
import socket
import sys
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, Callable
from urllib.parse import unquote, urlsplit

from camgen.errors import CamgenError, ParameterError
from camgen.serve.api import RequestError, SceneSource
from camgen.serve.files import FileStore

__all__ = ["CSP", "DEFAULT_PORT", "LOOPBACK_HOSTS", "MAX_BODY", "PageServer", "is_loopback", "make_server", "serve"]

#: The port ``camgen serve`` listens on unless told otherwise.
DEFAULT_PORT = 8765
#: Largest request body read, bytes (1 MiB: a scene file's own limit).
MAX_BODY = 1 << 20
#: Seconds a connection may stay silent before the server drops it.
REQUEST_TIMEOUT_S = 60
#: The names a browser on this machine sends in ``Host`` (with ``:PORT``).
LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "[::1]")
#: The page's Content-Security-Policy: nothing but this server and inline code.
CSP = "default-src 'self'; script-src 'unsafe-inline' 'self'; style-src 'unsafe-inline' 'self'; img-src 'self' data:"
#: ``GET /`` when the page file is not installed (a checkout without it).
_NO_PAGE = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>camgen serve</title></head><body>"
            "<p>camgen serve: the page (camgen/serve/page.html) is not installed; the API is at /api/scene, /api/schema, "
            "/api/evaluate, /api/save, /api/files.</p></body></html>")

#: path -> the methods it takes (a file download is ``/files/...``, GET only).
_ROUTES = {"/": ("GET",), "/api/scene": ("GET",), "/api/schema": ("GET",), "/api/evaluate": ("POST",), "/api/save": ("POST",),
           "/api/files": ("POST",)}
_MEDIA = {".dxf": "application/dxf", ".json": "application/json", ".html": "text/html; charset=utf-8", ".csv": "text/csv; charset=utf-8",
          ".svg": "image/svg+xml", ".stl": "model/stl", ".step": "model/step", ".ngc": "text/plain; charset=utf-8",
          ".pdf": "application/pdf", ".3mf": "model/3mf"}


def is_loopback(host: str) -> bool:
    """Whether ``host`` (an address or ``localhost``) is this machine's loopback interface."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def _page() -> bytes:
    from importlib.resources import files

    try:
        return (files("camgen.serve") / "page.html").read_bytes()
    except (FileNotFoundError, OSError):
        return _NO_PAGE.encode("utf-8")


class PageServer(ThreadingHTTPServer):
    """The server: the scene it was started with, the files it made, the schema (made once), the
    ``Host`` values it answers; ``stop_check`` is called between requests (a Ctrl-C stops it there)."""

    daemon_threads = True

    def __init__(self, address: tuple[str, int], source: SceneSource, stop_check: Callable[[], None] = lambda: None) -> None:
        self.address_family = socket.AF_INET6 if ":" in address[0] else socket.AF_INET
        super().__init__(address, _Handler)
        from camgen.serve.api import schema

        self.source = source
        self.store = FileStore()
        self.page = _page()
        self.schema_bytes = json.dumps(schema(), allow_nan=False).encode("utf-8")
        self.stop_check = stop_check
        port = self.server_address[1]
        bound = address[0] if ":" not in address[0] else f"[{address[0]}]"
        self.hosts = frozenset(f"{h}:{port}".lower() for h in LOOPBACK_HOSTS + (bound,))
        self.origins = frozenset(f"http://{h}" for h in self.hosts)

    @property
    def port(self) -> int:
        return int(self.server_address[1])

    def service_actions(self) -> None:
        self.stop_check()

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A connection that failed outside a request's handling (the browser closed it, a read
        timed out): nothing to answer; anything else one line, never a traceback."""
        exc = sys.exc_info()[1]
        if isinstance(exc, (ConnectionError, TimeoutError)):
            return
        print(f"camgen: internal error in a connection (a bug in camgen): {type(exc).__name__}: {' '.join(str(exc).split())[:200]}",
              file=sys.stderr, flush=True)


class _Handler(BaseHTTPRequestHandler):
    server: PageServer
    timeout = REQUEST_TIMEOUT_S
    server_version = "camgen-serve"
    sys_version = ""

    def log_message(self, format: str, *args: Any) -> None:  # one line per request would drown the URL line
        return None

    # -- answers ---------------------------------------------------------------------------------
    def _send(self, status: int, body: bytes, media: str, headers: dict[str, str] | None = None) -> None:
        self.send_response(status)
        self.send_header("Content-Type", media)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("X-Frame-Options", "DENY")
        self.send_header("Referrer-Policy", "no-referrer")
        for name, value in (headers or {}).items():
            self.send_header(name, value)
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(body)

    def _json(self, status: int, value: Any) -> None:
        self._send(status, json.dumps(value, allow_nan=False, default=str).encode("utf-8"), "application/json")

    def _refuse(self, status: int, message: str, headers: dict[str, str] | None = None) -> None:
        body = json.dumps({"error": {"key": None, "message": message}}).encode("utf-8")
        self.close_connection = True  # a body may be left unread: the connection cannot carry another request
        self._send(status, body, "application/json", headers)

    # -- routing ---------------------------------------------------------------------------------
    def _route(self) -> str | None:
        """The request's path if the Host header and the path pass (else answered here, None)."""
        host = (self.headers.get("Host") or "").strip().lower()
        if host not in self.server.hosts:
            self._refuse(403, "camgen serve answers only requests addressed to it on this machine (Host header)")
            return None
        origin = self.headers.get("Origin")
        if origin is not None and origin.strip().lower() not in self.server.origins:
            self._refuse(403, "camgen serve answers only its own page (Origin header)")
            return None
        raw = urlsplit(self.path).path
        path = unquote(raw)
        if ".." in path or "\\" in path or "\x00" in path or "//" in path or not path.startswith("/"):
            self._refuse(404, "not found")
            return None
        return path

    def _allowed(self, path: str) -> tuple[str, ...] | None:
        if path in _ROUTES:
            return _ROUTES[path]
        parts = path.split("/")
        if len(parts) == 4 and parts[1] == "files" and parts[2] and parts[3]:
            return ("GET",)
        return None

    def _known_path(self) -> tuple[str, tuple[str, ...]] | None:
        """The request's path and the methods it takes; None when refused (an answer sent)."""
        path = self._route()
        if path is None:
            return None
        allowed = self._allowed(path)
        if allowed is None:
            self._refuse(404, "not found")
            return None
        return path, allowed

    def _dispatch(self) -> None:
        known = self._known_path()
        if known is None:
            return
        path, allowed = known
        if self.command not in allowed:
            self._refuse(405, f"{path} takes {', '.join(allowed)} only", {"Allow": ", ".join(allowed)})
            return
        if self.command == "GET" and self.headers.get("Content-Length", "0").strip() not in ("", "0"):
            self.close_connection = True  # a GET's body is never read: the connection cannot carry another request
        try:
            if self.command == "GET":
                self._get(path)
            else:
                self._post(path)
        except (ConnectionError, TimeoutError):  # the browser went away or stopped sending: nothing to answer
            self.close_connection = True
        except RequestError as exc:
            self._refuse(400, f"camgen: error: {exc}")
        except CamgenError as exc:  # a refusal the API did not turn into an answer
            self._refuse(400, f"camgen: error: {' '.join(str(exc).split())}")
        except Exception as exc:  # a bug: one line on the server's terminal and in the answer, never a traceback
            line = (f"camgen: internal error (a bug in camgen, not a verdict on the design): {type(exc).__name__}: "
                    f"{' '.join(str(exc).split())[:200]}")
            print(line, file=sys.stderr, flush=True)
            self._refuse(500, line)

    def _get(self, path: str) -> None:
        from camgen.serve.api import scene_json

        if path == "/":
            self._send(200, self.server.page, "text/html; charset=utf-8", {"Content-Security-Policy": CSP})
        elif path == "/api/scene":
            self._json(200, scene_json(self.server.source))
        elif path == "/api/schema":
            self._send(200, self.server.schema_bytes, "application/json")
        else:
            _, _, token, name = path.split("/")
            data = self.server.store.get(token, name)
            if data is None:
                self._refuse(404, "no such file: downloads are of files this server made (ask /api/files again)")
                return
            suffix = name[name.rfind("."):].lower() if "." in name else ""
            safe = "".join(c if c.isalnum() or c in "._-" else "_" for c in name)
            self._send(200, data, _MEDIA.get(suffix, "application/octet-stream"),
                       {"Content-Disposition": f'attachment; filename="{safe}"', "Content-Security-Policy": "default-src 'none'; sandbox"})

    def _body(self) -> object | None:
        media = (self.headers.get("Content-Type") or "").split(";")[0].strip().lower()
        if media != "application/json":
            self._refuse(415, "a POST body must be JSON (Content-Type: application/json)")
            return None
        length_text = self.headers.get("Content-Length")
        if length_text is None:
            self._refuse(411, "a POST body needs a Content-Length")
            return None
        try:
            length = int(length_text)
        except ValueError:
            length = -1
        if length < 0:
            self._refuse(400, "the Content-Length is not a length")
            return None
        if length > MAX_BODY:
            self._refuse(413, f"a request body may be at most {MAX_BODY} bytes, this one has {length}")
            return None
        raw = self.rfile.read(length)
        try:
            return json.loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError):
            self._refuse(400, "the request body is not JSON (UTF-8)")
            return None

    def _post(self, path: str) -> None:
        from camgen.serve.api import evaluate, make_files, save

        body = self._body()
        if body is None:
            return
        source = self.server.source
        if path == "/api/evaluate":
            self._json(200, evaluate(source, body))
        elif path == "/api/save":
            self._json(200, save(source, body))
        else:
            self._json(200, make_files(source, body, self.server.store))

    do_GET = do_POST = _dispatch

    def _not_allowed(self) -> None:
        known = self._known_path()
        if known is not None:
            path, allowed = known
            self._refuse(405, f"{path} takes {', '.join(allowed)} only", {"Allow": ", ".join(allowed)})

    do_PUT = do_DELETE = do_PATCH = do_OPTIONS = do_HEAD = do_TRACE = do_CONNECT = _not_allowed


def make_server(scene: str | None, host: str = "127.0.0.1", port: int = DEFAULT_PORT, allow_remote: bool = False,
                stop_check: Callable[[], None] = lambda: None) -> PageServer:
    """A :class:`PageServer` for the scene file ``scene`` (None: the bundled default scene),
    listening on ``host``:``port`` (port 0: a free port the system picks).

    Raises
    ------
    ParameterError
        ``--host`` not a loopback address without ``allow_remote``; ``--port`` out of range, taken,
        or not allowed (naming the port and suggesting another).
    SceneError
        The scene file cannot be read or is not TOML.
    """
    from camgen.serve.api import load_source

    if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
        raise ParameterError("--port", port, "a TCP port number, 0 <= N <= 65535 (0: any free port)")
    if not host or not host.strip():
        raise ParameterError("--host", host, "an address to listen on (default 127.0.0.1)")
    if not is_loopback(host) and not allow_remote:
        raise ParameterError("--host", host, "a loopback address (127.0.0.1, ::1, localhost) unless --allow-remote is given",
                             "the server has no authentication: anyone who reaches the port can use it")
    source = load_source(scene)
    try:
        return PageServer((host.strip("[]"), port), source, stop_check)
    except OSError as exc:
        if exc.errno == errno.EADDRINUSE:
            raise ParameterError("--port", port, "a free TCP port", f"port {port} on {host} is taken by another program: "
                                 "choose another with --port N") from None
        raise ParameterError("--host/--port", f"{host}:{port}", "an address and port this machine can listen on",
                             " ".join(str(exc.strerror or exc).split())) from None


def _warm_up(source: SceneSource) -> None:
    """Evaluate the scene once while the user opens the page: the first edit then finds every
    module imported (the first evaluation takes several times longer than the next).  Its answer is
    dropped; an error it meets is met again, and shown, by the page's own first request."""
    from camgen.serve.api import evaluate

    try:
        evaluate(source, {"seq": 0, "data": dict(source.data)})
    except Exception:  # noqa: BLE001 - shown by the page's own request
        return


def serve(scene: str | None, host: str = "127.0.0.1", port: int = DEFAULT_PORT, allow_remote: bool = False) -> int:
    """``camgen serve``: serve the live page of ``scene`` until SIGINT/SIGTERM (which end the
    command as every other: :class:`camgen.interrupt.Interrupted`, exit 130/143)."""
    from camgen.interrupt import checkpoint

    server = make_server(scene, host, port, allow_remote, checkpoint)
    threading.Thread(target=_warm_up, args=(server.source,), name="camgen-serve-warm-up", daemon=True).start()
    try:
        if not is_loopback(host):
            print(f"camgen: warning: serving on {host}, not only this machine: the server has no authentication, anyone who "
                  "reaches the port can use it", file=sys.stderr, flush=True)
        shown = f"[{host.strip('[]')}]" if ":" in host else host
        print(f"camgen: serving {server.source.source} at http://{shown}:{server.port}/ (Ctrl-C stops it)", flush=True)
        server.serve_forever(poll_interval=0.2)
    finally:
        server.server_close()
    return 0
