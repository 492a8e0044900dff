"""A bare websocket client that sends any frame and never answers a ping (tests only).

Libraries answer pings for their user and refuse to send after a close: this one is the client a
server must survive, the one whose pings time out and who keeps sending after the server closed.
"""

from __future__ import annotations

import base64
import os
import socket
import struct
import threading


class RawWebSocket:
    """One websocket over a plain TCP socket: ``send`` any bytes, read and drop what comes back.

    ``closed_by_server`` is set when the server's close frame arrives (it is never answered), with its
    ``close_code`` (None: no code); ``ended`` when the server dropped the connection."""

    def __init__(self, host: str, port: int, path: str, *, subprotocol: str, origin: str, timeout: float = 60) -> None:
        self.sock = socket.create_connection((host, port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        request = (
            f"GET {path} HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: {subprotocol}\r\n"
            f"Origin: {origin}\r\n\r\n"
        )
        self.sock.sendall(request.encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError(f"closed during the handshake: {head!r}")
            head += chunk
        self.status = int(head.split(b" ", 2)[1])
        self.closed_by_server = threading.Event()
        self.close_code: int | None = None
        self.ended = threading.Event()
        self._rest = head.split(b"\r\n\r\n", 1)[1]
        self._reader = threading.Thread(target=self._read, daemon=True)
        if self.status == 101:
            self._reader.start()

    def send(self, payload: bytes, opcode: int = 0x2) -> bool:
        """One masked frame; False when the connection is gone."""
        mask = os.urandom(4)
        n = len(payload)
        if n < 126:
            head = struct.pack("!BB", 0x80 | opcode, 0x80 | n)
        elif n < 1 << 16:
            head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, n)
        else:
            head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, n)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        try:
            self.sock.sendall(head + mask + masked)
        except OSError:
            return False
        return True

    def _read(self) -> None:
        """Drain the server's frames (so its output never queues for us); note its close frame."""
        buf = self._rest
        try:
            while True:
                while len(buf) >= 2:
                    size, start = buf[1] & 0x7F, 2
                    if size == 126:
                        if len(buf) < 4:
                            break
                        size, start = struct.unpack("!H", buf[2:4])[0], 4
                    elif size == 127:
                        if len(buf) < 10:
                            break
                        size, start = struct.unpack("!Q", buf[2:10])[0], 10
                    if len(buf) < start + size:
                        break
                    if buf[0] & 0x0F == 0x8:
                        payload = buf[start : start + size]
                        self.close_code = struct.unpack("!H", payload[:2])[0] if size >= 2 else None
                        self.closed_by_server.set()
                    buf = buf[start + size :]
                chunk = self.sock.recv(1 << 16)
                if not chunk:
                    return
                buf += chunk
        except OSError:
            return
        finally:
            self.ended.set()

    def close(self) -> None:
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.sock.close()
