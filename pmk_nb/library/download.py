"""HTTP(S) download with a stall timeout, an overall deadline, a size cap and errors a user can act on.

The original app (thesis 4.2.1.3 a) fetched the whole body into memory and showed one generic
"check your connection" dialog. Here the body streams to a file the caller owns, the size is capped
(checked against Content-Length first, then while reading), a short body is detected, and each
failure names its cause: bad URL, DNS, refused connection, HTTP status, timeout, too big.
"""

from __future__ import annotations

import http.client
import socket
import ssl
import time
import urllib.error
import urllib.request
from collections.abc import Callable
from typing import IO
from urllib.parse import urlsplit

from pmk_nb import __version__
from pmk_nb.errors import DownloadError, DownloadTooLarge, LibraryError
from pmk_nb.library.netguard import guarded_handlers
from pmk_nb.progress import ProgressCallback, emit

DEFAULT_TIMEOUT = 30.0  # seconds without any data (a stall)
DEFAULT_DEADLINE = 120.0  # seconds for the whole download, however steadily it trickles
DEFAULT_MAX_BYTES = 50 * 1024 * 1024
_CHUNK = 64 * 1024
_SCHEMES = ("http", "https")


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


#: Called with (URL, redirect target) before a redirect is followed; raises to refuse it.
RedirectCheck = Callable[[str, str], None]


class _HttpOnlyRedirects(urllib.request.HTTPRedirectHandler):
    """Follow redirects, but never off http(s) (urllib would follow one to ftp:), and only where
    the caller's check allows (a map catalogue keeps to its own scheme and folder)."""

    def __init__(self, check: RedirectCheck | None = None) -> None:
        super().__init__()
        self.check = check

    def redirect_request(
        self,
        req: urllib.request.Request,
        fp: IO[bytes],
        code: int,
        msg: str,
        headers: http.client.HTTPMessage,
        newurl: str,
    ) -> urllib.request.Request | None:
        if urlsplit(newurl).scheme.lower() not in _SCHEMES:
            raise DownloadError(
                f"download of {req.full_url} refused: the server redirects to {newurl!r}", url=req.full_url
            )
        if self.check is not None:
            self.check(req.full_url, newurl)
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
    deadline: float = DEFAULT_DEADLINE,
    max_bytes: int = DEFAULT_MAX_BYTES,
    progress: ProgressCallback | None = None,
    allow_local: bool = False,
    redirect_check: RedirectCheck | None = None,
) -> int:
    """Stream the body of ``url`` into ``out``.

    Args:
        url: an http:// or https:// URL (redirects are followed, only to http(s)).
        out: a binary file the caller opened (and removes if this raises).
        timeout: seconds to wait for the connection and for each piece of data (a stall timeout).
        deadline: seconds the whole download may take: a server trickling bytes just fast enough to
            beat ``timeout`` is cut off here.
        max_bytes: the download is refused past this many bytes.
        progress: ``download`` reports; the fraction is None when the server sends no Content-Length.
        allow_local: also reach loopback, LAN and other non-public addresses (labs); by default the
            host and every redirect's host must resolve to public addresses only
            (:mod:`pmk_nb.library.netguard`).
        redirect_check: called with (URL, target) before each redirect is followed; raising refuses it.

    Returns:
        The number of bytes written.

    Raises:
        DownloadError: naming the cause (redirect, DNS, refused, HTTP status, timeout, deadline, size,
            short body); AddressRefused for a non-public address; LibraryError for a malformed URL.
    """
    _, host = check_url(url)
    opener = urllib.request.build_opener(_HttpOnlyRedirects(redirect_check), *guarded_handlers(allow_local))
    request = urllib.request.Request(
        url.strip(), headers={"User-Agent": f"pmk-nb/{__version__}", "Accept": "application/xml, text/xml, */*"}
    )
    ends_at = time.monotonic() + deadline
    try:
        with opener.open(request, timeout=min(timeout, deadline)) as response:
            return _copy_body(response, out, url=url, max_bytes=max_bytes, ends_at=ends_at, progress=progress)
    except urllib.error.HTTPError as err:
        hint = "; check the URL" if err.code in (400, 403, 404, 410) else ""
        msg = f"download of {url} failed: the server answered HTTP {err.code} {err.reason}{hint}"
        raise DownloadError(msg, url=url) from err
    except urllib.error.URLError as err:
        why = _describe_reason(err.reason, host, timeout)
        raise DownloadError(f"download of {url} failed: {why}", url=url) from err
    except TimeoutError as err:
        raise DownloadError(
            f"download of {url} failed: no data from {host} for {timeout:g} s (timed out).",
            url=url,
            hint="Try again or raise the timeout.",
        ) from err
    except (http.client.HTTPException, OSError) as err:
        raise DownloadError(f"download of {url} failed: the connection to {host} broke ({err!r})", url=url) from err


def _copy_body(
    response: http.client.HTTPResponse,
    out: IO[bytes],
    *,
    url: str,
    max_bytes: int,
    ends_at: float,
    progress: ProgressCallback | None,
) -> int:
    total = _content_length(response)
    if total is not None and total > max_bytes:
        raise DownloadTooLarge(
            f"download of {url} refused: the file is {_mib(total)}, more than the limit of {_mib(max_bytes)}",
            url=url,
            limit=max_bytes,
            size=total,
        )
    done = 0
    emit(progress, "download", 0.0 if total else None, _amount(0, total))
    while chunk := response.read1(_CHUNK):
        done += len(chunk)
        if done > max_bytes:
            msg = f"download of {url} aborted: more than the limit of {_mib(max_bytes)} received"
            raise DownloadTooLarge(msg, url=url, limit=max_bytes, size=done)
        out.write(chunk)
        emit(progress, "download", done / total if total else None, _amount(done, total))
        if time.monotonic() > ends_at:
            raise DownloadError(
                f"download of {url} aborted: not finished within the deadline ({_mib(done)} received).",
                url=url,
                hint="The server is too slow: try again later or raise the deadline.",
            )
    if total is not None and done < total:
        # http.client returns a short body silently when the server closes early
        raise DownloadError(
            f"download of {url} incomplete: the connection closed after {done} of {total} bytes.",
            url=url,
            hint="Try again.",
        )
    out.flush()
    return done


def _amount(done: int, total: int | None) -> str:
    return f"{_mib(done)} of {_mib(total)}" if total else _mib(done)


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
