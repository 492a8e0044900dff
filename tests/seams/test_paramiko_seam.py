"""The paramiko internal pmk_nb/seams/paramiko_seam.py overrides is still there, in the pinned version."""

from __future__ import annotations

import errno
import inspect

import paramiko
import pytest
from paramiko.message import Message
from paramiko.sftp import SFTP_NO_SUCH_FILE, SFTP_OK, SFTP_OP_UNSUPPORTED

from pmk_nb.chair.ssh import SftpUnsupported, StatusSFTPClient
from pmk_nb.seams.paramiko_seam import TOUCHED, StatusHookSFTPClient
from tests.seam_pins import assert_pinned_and_installed


def test_installed_paramiko_is_the_pinned_version() -> None:
    assert_pinned_and_installed("paramiko")


def test_status_replies_still_go_through_convert_status() -> None:
    assert TOUCHED == ("_convert_status",)
    source = inspect.getsource(paramiko.SFTPClient._convert_status)
    assert list(inspect.signature(paramiko.SFTPClient._convert_status).parameters) == ["self", "msg"]
    assert "code = msg.get_int()" in source and "text = msg.get_text()" in source
    assert "raise IOError(text)" in source  # an unknown code keeps only the text: why the hook exists
    callers = inspect.getsource(paramiko.SFTPClient._read_response)
    assert "self._convert_status(msg)" in callers


def _status(code: int, text: str) -> Message:
    msg = Message()
    msg.add_int(code)
    msg.add_string(text)
    msg.rewind()
    return msg


def test_the_hook_sees_the_code_and_paramiko_still_converts_the_rest() -> None:
    client = StatusSFTPClient.__new__(StatusSFTPClient)  # no channel: only the status conversion runs
    assert isinstance(client, StatusHookSFTPClient)
    with pytest.raises(SftpUnsupported) as unsupported:
        client._convert_status(_status(SFTP_OP_UNSUPPORTED, "no posix-rename"))
    assert unsupported.value.errno == errno.EOPNOTSUPP and "no posix-rename" in str(unsupported.value)
    with pytest.raises(OSError) as missing:
        client._convert_status(_status(SFTP_NO_SUCH_FILE, "gone"))
    assert missing.value.errno == errno.ENOENT and not isinstance(missing.value, SftpUnsupported)
    assert client._convert_status(_status(SFTP_OK, "")) is None
