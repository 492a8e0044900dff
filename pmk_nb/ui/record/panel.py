"""Home's Record panel: Record / Stop recording, the running recording's time, messages and file,
download links for the finished recording and for the current map (YAML + image, zipped),
**Replay** of the finished recording (:mod:`.replay`: pose, laser, path and a plot following a time
slider), and **Open**: any MCAP of the recordings folder (ours, ``ros2 bag``'s, Foxglove's), or one
uploaded from this device into it, replayed the same way.

Recordings go in ``recordings/`` beside the maps folder (``MapsFolder.root``'s parent), one MCAP
file per recording named by its start time. Starting writes files on the tablet, so on a locked
kiosk page it needs the PIN (:func:`~pmk_nb.ui.common.context.needs_pin`); stopping never does. The link
calls (rosapi topic list, opening the recording's connection) run in a thread, never in a widget
callback; a 2 Hz loop updates the status while a recording runs.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.recordings import RecordingFileError, list_recordings, recording_in, save_upload
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.upload import uploaded_file
from pmk_nb.ui.common.widgets import TOUCH_PX, button, escape, guard, html_slot, run_in_thread
from pmk_nb.ui.live.render_loop import RenderLoop
from pmk_nb.ui.record.downloads import file_link_html, link_html, map_zip
from pmk_nb.ui.record.replay import ReplayView

if TYPE_CHECKING:
    from pmk_nb.chair.link import Recording, RecordStats
    from pmk_nb.ui.common.context import AppContext

STATUS_HZ = 2.0


def recordings_dir(ctx: AppContext) -> Path:
    """Where the dashboard keeps recordings: ``recordings/`` beside the maps folder."""
    return ctx.maps.root.parent / "recordings"


def status_text(seconds: float, messages: int, dropped: int, name: str) -> str:
    clock = f"{int(seconds) // 60}:{int(seconds) % 60:02d}"
    dropped_text = f", {dropped} dropped" if dropped else ""
    return f"Recording {clock} · {messages} messages{dropped_text} · {escape(name)}"


class RecordPanel:
    """The Record button, its status line and the download links; ``widget`` goes under the map."""

    def __init__(self, ctx: AppContext) -> None:
        self.ctx = ctx
        self.recording: Recording | None = None
        self._busy = threading.Lock()  # one start or stop at a time, whatever the page sends
        self.record_button = button("Record", "pmk-record-start", icon="circle", tooltip="Record the chair's topics")
        self.stop_button = button("Stop recording", "pmk-record-stop", icon="stop")
        self.map_button = button("Download map", "pmk-record-map", icon="download", tooltip="The current map as a zip")
        self.replay_button = button("Replay", "pmk-record-replay", icon="play", tooltip="Replay the finished recording")
        self.finished: Path | None = None  # the last recording this panel finished
        self.replay_view: ReplayView | None = None
        self.replay_slot = w.VBox([])
        self.files = w.Dropdown(options=[], description="Recording", layout=w.Layout(width="auto", max_width="28em"))
        self.files.add_class("pmk-record-files")
        self.open_button = button("Open", "pmk-record-open", icon="folder-open", tooltip="Replay the chosen recording")
        self.refresh_button = button("", "pmk-record-refresh", icon="refresh", tooltip="List the recordings again")
        self.upload = w.FileUpload(
            accept=".mcap", multiple=False, description="Upload MCAP", tooltip="Replay an MCAP file from this device"
        )
        self.upload.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto")
        self.upload.add_class("pmk-record-upload")
        self.open_status = html_slot("pmk-record-open-status")
        self.status = html_slot("pmk-record-status")
        self.downloads = html_slot("pmk-record-downloads")
        self.map_link = html_slot("pmk-record-map-link")
        self.record_button.on_click(guard(ctx, "Recording")(lambda _b: self.start()))
        self.stop_button.on_click(guard(ctx, "Stopping the recording")(lambda _b: self.stop()))
        self.map_button.on_click(guard(ctx, "Downloading the map")(lambda _b: self.offer_map()))
        self.replay_button.on_click(guard(ctx, "Opening the replay")(lambda _b: self.replay()))
        self.open_button.on_click(guard(ctx, "Opening the recording")(lambda _b: self.open_chosen()))
        self.refresh_button.on_click(guard(ctx, "Listing the recordings")(lambda _b: self.list_files()))
        self.upload.observe(guard(ctx, "Uploading a recording")(self._on_upload), names="value")
        # wraps on a narrow screen (a phone) instead of making the page scroll sideways
        row = w.HBox(
            [self.record_button, self.stop_button, self.replay_button, self.map_button, self.status],
            layout=w.Layout(flex_flow="row wrap", align_items="center", max_width="100%"),
        )
        row.add_class("pmk-record-row")
        open_row = w.HBox(
            [self.files, self.open_button, self.refresh_button, self.upload],
            layout=w.Layout(flex_flow="row wrap", align_items="center", max_width="100%"),
        )
        open_row.add_class("pmk-record-open-row")
        self.widget = w.VBox([row, self.downloads, self.map_link, open_row, self.open_status, self.replay_slot])
        self.widget.add_class("pmk-record")
        self._loop = RenderLoop(self.refresh, STATUS_HZ)
        self._show(False)
        self.list_files()

    def _show(self, running: bool) -> None:
        self.record_button.layout.display = "none" if running else ""
        self.stop_button.layout.display = "" if running else "none"
        self.replay_button.layout.display = "" if self.finished is not None and not running else "none"

    @needs_pin("Recording")
    def start(self) -> threading.Thread | None:
        """Start recording the chair's default topics in a thread (the link asks rosapi first)."""
        if self.recording is not None:
            return None
        link = self.ctx.link()
        name = time.strftime("rec-%Y%m%d-%H%M%S.mcap")
        folder = recordings_dir(self.ctx)

        def work() -> Recording:
            folder.mkdir(parents=True, exist_ok=True)
            link.connect(timeout=5.0)
            return link.start_recording(folder / name)

        self.status.value = f"Starting the recording {escape(name)}…"
        self.downloads.value = ""
        return run_in_thread(
            self.ctx, "Recording", work, on_done=self._started, on_error=self._failed, exclusive=self._busy
        )

    def _started(self, recording: Recording) -> None:
        self.recording = recording
        self._show(True)
        self.refresh()
        self._loop.start()

    def _failed(self, err: BaseException) -> None:
        self.status.value = f'<span class="pmk-record-error">Not recording: {escape(err)}</span>'

    def refresh(self) -> None:
        """The running recording's time, message count and file name."""
        recording = self.recording
        if recording is not None and recording.error is not None:  # the disk failed: stop and say why
            self.stop()
        elif recording is not None:
            stats = recording.stats
            seconds = time.time() - stats.started
            self.status.value = status_text(seconds, stats.total, stats.dropped, recording.path.name)

    def stop(self) -> threading.Thread | None:
        """Finish the file (in a thread: the writer flushes what is queued) and offer its download."""
        recording = self.recording
        if recording is None:
            return None
        self._loop.stop()

        def work() -> RecordStats:
            try:
                return recording.stop()
            finally:
                self.recording = None
                self._show(False)

        return run_in_thread(
            self.ctx, "Stopping the recording", work, on_done=self._stopped, on_error=self._failed, exclusive=self._busy
        )

    def _stopped(self, stats: RecordStats) -> None:
        path = stats.path
        said = f"Recorded {stats.total} messages in {stats.duration:.0f} s: recordings/{escape(path.name)}"
        if stats.silent:  # a parked chair sends no /cmd_vel: say so rather than let the file look short
            said += f" · no message on {escape(', '.join(stats.silent))}"
        self.status.value = said
        self.downloads.value = file_link_html(path, f"Download {path.name}", "pmk-record-link")
        self.finished = path
        self._show(False)
        self.list_files(select=path.name)

    def replay(self) -> threading.Thread | None:
        """Open the finished recording's replay under the panel (the file is read in a thread)."""
        path = self.finished
        if path is None:
            return None

        return self._open(path, "Opening the replay")

    def _open(self, path: Path, action: str) -> threading.Thread | None:
        """Read ``path`` in a thread and show its replay under the panel (or say why it cannot be read)."""
        self.open_status.value = f"Opening {escape(path.name)}…"

        def opened(view: ReplayView) -> None:
            self.replay_view = view
            self.replay_slot.children = [view.widget]
            topics = len(view.timeline.numeric_fields())
            self.open_status.value = (
                f"Replaying {escape(path.name)}: {view.timeline.duration:.1f} s"
                + ("" if view.timeline.pose_topic else " · no pose topic: nothing to show on the map")
                + ("" if topics else " · no numeric field to plot")
            )

        def failed(err: BaseException) -> None:
            self.open_status.value = f'<span class="pmk-record-error">{escape(err)}</span>'

        return run_in_thread(self.ctx, action, lambda: ReplayView(path), on_done=opened, on_error=failed)

    def list_files(self, select: str | None = None) -> None:
        """List the recordings folder in the picker (newest first), keeping (or making) ``select`` the choice."""
        found = list_recordings(recordings_dir(self.ctx))
        keep = select if select is not None else self.files.value
        self.files.options = [(r.label, r.name) for r in found]
        names = [r.name for r in found]
        self.files.value = keep if keep in names else (names[0] if names else None)
        self.open_button.disabled = not names

    def open_chosen(self) -> threading.Thread | None:
        """Replay the recording chosen in the picker (looked up again: the page may send any name)."""
        try:
            path = recording_in(recordings_dir(self.ctx), self.files.value)
        except RecordingFileError as err:
            self._refused(err)
            self.list_files()
            return None
        return self._open(path, "Opening the recording")

    def _refused(self, err: RecordingFileError) -> None:
        hint = f" {err.hint}" if err.hint else ""
        self.open_status.value = f'<span class="pmk-record-error">{escape(err.message)}.{escape(hint)}</span>'

    def _on_upload(self, change: dict[str, Any]) -> None:
        got = uploaded_file(change)
        if got is None:
            return
        self.upload.value = ()  # so the same file can be chosen again
        self.store_upload(*got)

    @needs_pin("Uploading a recording")
    def store_upload(self, name: str, data: bytes) -> threading.Thread | None:
        """Keep an uploaded MCAP in the recordings folder (replacing nothing) and replay it."""
        try:
            path = save_upload(recordings_dir(self.ctx), name, data)
        except RecordingFileError as err:
            self._refused(err)
            return None
        self.list_files(select=path.name)
        return self._open(path, "Opening the recording")

    def offer_map(self) -> None:
        """A download link for the current map's YAML and image, zipped."""
        current = self.ctx.current_map
        if current is None:
            self.map_link.value = "No current map to download."
            return
        zip_name, data = map_zip(current.yaml)
        self.map_link.value = link_html(data, zip_name, f"Download {zip_name}", "pmk-map-link", "application/zip")

    def close(self) -> None:
        """Finish a running recording (a page that closes must not leave a file unwritten)."""
        self._loop.stop()
        recording, self.recording = self.recording, None
        if recording is not None:
            recording.stop()
