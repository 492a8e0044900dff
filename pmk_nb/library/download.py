"""HTTP(S) download with a stall timeout, a size cap and errors a user can act on.

The original app (thesis 4.2.1.3 a) fetched the whole body into memory and showed one generic
"check your connection" dialog. Here the body streams to a file the caller owns, the size is capped
(checked against Content-Length first, then while reading), a short body is detected, and each
failure names its cause: bad URL, DNS, refused connection, HTTP status, timeout, too big.
"""

from __future__ import annotations

import http.client
import socket
import ssl
import urllib.error
import urllib.request
from collections.abc import Callable
from typing import IO, Any
from urllib.parse import urlsplit

from pmk_nb import __version__
from pmk_nb.errors import LibraryError

DEFAULT_TIMEOUT = 30.0
DEFAULT_MAX_BYTES = 50 * 1024 * 1024
_CHUNK = 64 * 1024
_SCHEMES = ("http", "https")

Progress = Callable[[int, int | None], None]


def check_url(url: str) -> tuple[str, str]:
    """Return (scheme, host) of an http(s) URL or raise LibraryError saying what is wrong with it."""
    try:
        parts = urlsplit(url.strip())
        port = parts.port  # raises ValueError on a bad port
    except ValueError as err:
        raise LibraryError(f"{url!r} is not a valid URL: {err}") from err
    scheme = parts.scheme.lower()
    if scheme not in _SCHEMES:
        shown = f"'{scheme}:'" if scheme else "no scheme"
        raise LibraryError(
            f"cannot download {url!r}: only http:// and https:// URLs are supported ({shown} given); "
            "use import for a local file"
        )
    if not parts.hostname:
        raise LibraryError(f"cannot download {url!r}: the URL has no host name")
    host = parts.hostname if port is None else f"{parts.hostname}:{port}"
    return scheme, host


class _HttpOnlyRedirects(urllib.request.HTTPRedirectHandler):
    """Follow redirects, but never off http(s) (urllib would follow one to ftp:)."""

    def redirect_request(self, req: Any, fp: Any, code: int, msg: str, headers: Any, newurl: str) -> Any:
        if urlsplit(newurl).scheme.lower() not in _SCHEMES:
            raise LibraryError(f"download of {req.full_url} refused: the server redirects to {newurl!r}")
        return super().redirect_request(req, fp, code, msg, headers, newurl)


def _describe_reason(reason: object, host: str, timeout: float) -> str:
    if isinstance(reason, socket.gaierror):
        return f"cannot resolve host {host.rsplit(':', 1)[0]!r} (DNS failure); check the URL and the network"
    if isinstance(reason, ConnectionRefusedError):
        return f"connection to {host} refused; is the server running and the port right?"
    if isinstance(reason, TimeoutError):
        return f"no answer from {host} (timed out); the host is unreachable or too slow"
    if isinstance(reason, ssl.SSLCertVerificationError):
        return f"TLS certificate of {host} not trusted: {reason.verify_message}"
    if isinstance(reason, ssl.SSLError):
        return f"TLS error talking to {host}: {reason}"
    if isinstance(reason, OSError):
        return f"cannot reach {host}: {reason.strerror or reason}"
    return f"cannot reach {host}: {reason}"


def fetch(
    url: str,
    out: IO[bytes],
    *,
    timeout: float = DEFAULT_TIMEOUT,
    max_bytes: int = DEFAULT_MAX_BYTES,
    progress: Progress | None = None,
) -> int:
    """Stream the body of ``url`` into ``out``.

    Args:
        url: an http:// or https:// URL (redirects are followed, only to http(s)).
        out: a binary file the caller opened (and removes if this raises).
        timeout: seconds to wait for the connection and for each piece of data (a stall timeout,
            so a slow but steady big download still completes).
        max_bytes: the download is refused past this many bytes.
        progress: called as ``progress(bytes_so_far, total_or_None)``.

    Returns:
        The number of bytes written.

    Raises:
        LibraryError: naming the cause (URL, DNS, refused, HTTP status, timeout, size, short body).
    """
    _, host = check_url(url)
    opener = urllib.request.build_opener(_HttpOnlyRedirects)
    request = urllib.request.Request(
        url.strip(), headers={"User-Agent": f"pmk-nb/{__version__}", "Accept": "application/xml, text/xml, */*"}
    )
    try:
        with opener.open(request, timeout=timeout) as response:
            return _copy_body(response, out, url=url, max_bytes=max_bytes, progress=progress)
    except urllib.error.HTTPError as err:
        hint = "; check the URL" if err.code in (400, 403, 404, 410) else ""
        raise LibraryError(f"download of {url} failed: the server answered HTTP {err.code} {err.reason}{hint}") from err
    except urllib.error.URLError as err:
        raise LibraryError(f"download of {url} failed: {_describe_reason(err.reason, host, timeout)}") from err
    except TimeoutError as err:
        raise LibraryError(
            f"download of {url} failed: no data from {host} for {timeout:g} s (timed out); try again "
            "or raise the timeout"
        ) from err
    except (http.client.HTTPException, OSError) as err:
        raise LibraryError(f"download of {url} failed: the connection to {host} broke ({err!r})") from err


def _copy_body(
    response: http.client.HTTPResponse, out: IO[bytes], *, url: str, max_bytes: int, progress: Progress | None
) -> int:
    total = _content_length(response)
    if total is not None and total > max_bytes:
        raise LibraryError(
            f"download of {url} refused: the file is {_mib(total)}, more than the limit of {_mib(max_bytes)}"
        )
    done = 0
    if progress:
        progress(0, total)
    while chunk := response.read(_CHUNK):
        done += len(chunk)
        if done > max_bytes:
            raise LibraryError(f"download of {url} aborted: more than the limit of {_mib(max_bytes)} received")
        out.write(chunk)
        if progress:
            progress(done, total)
    if total is not None and done < total:
        # http.client returns a short body silently when the server closes early
        raise LibraryError(
            f"download of {url} incomplete: the connection closed after {done} of {total} bytes; try again"
        )
    out.flush()
    return done


def _content_length(response: http.client.HTTPResponse) -> int | None:
    raw = response.headers.get("Content-Length")
    if raw is None:
        return None
    try:
        value = int(raw.strip())
    except ValueError:
        return None
    return value if value >= 0 else None


def _mib(n: int) -> str:
    return f"{n / (1024 * 1024):.1f} MiB" if n >= 1024 * 1024 else f"{n} bytes"
