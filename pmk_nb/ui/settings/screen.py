"""Settings screen: how to reach the wheelchair, saved as a chair profile, with a connection test.

As in the original (thesis 5.2.3.2): a form (name, address, rosbridge port, topics, SSH user and
password), Save, and Test connection whose status goes Disconnected -> Connecting -> Connected
with the published map's width, height and resolution in the information panel.  Saved values are
the defaults next time; the password goes to :class:`ProfileStore` (keyring or session memory),
never to a file.  A successful test fills the topic pickers with what the chair publishes.
"""

from __future__ import annotations

import dataclasses
import threading
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.chair import AUTH_METHODS, POSE_SOURCES, ChairProfile
from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH
from pmk_nb.errors import PmkError, SettingsError
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.widgets import (
    TOUCH_PX,
    button,
    error_text,
    escape,
    field_error,
    guard,
    heading,
    run_in_thread,
    text,
)
from pmk_nb.ui.kiosk.mode import pin_section
from pmk_nb.ui.settings.host_key_prompt import CertificatePrompt

if TYPE_CHECKING:
    from pmk_nb.chair.link import ConnectionReport
    from pmk_nb.ui.common.context import AppContext

TEST_TIMEOUT = 5.0
TOPIC_TYPES: dict[str, tuple[str, ...]] = {
    "odom_topic": ("nav_msgs/Odometry", "nav_msgs/msg/Odometry"),
    "scan_topic": ("sensor_msgs/LaserScan", "sensor_msgs/msg/LaserScan"),
    "pose_topic": ("geometry_msgs/PoseWithCovarianceStamped", "geometry_msgs/msg/PoseWithCovarianceStamped"),
    "cmd_vel_topic": ("geometry_msgs/Twist", "geometry_msgs/msg/Twist"),
}
_DEFAULTS = {f.name: f.default for f in dataclasses.fields(ChairProfile)}
#: Driving fields (numbers) and their labels; the profile checks the ranges.
DRIVE_NUMBERS = {
    "max_linear": "Top speed (m/s)",
    "max_angular": "Top turning speed (rad/s)",
    "slow_factor": "Slow mode (0.4 = 40 % speed)",
}
_POSE_LABELS = {"odometry": "Odometry", "pose_topic": "Pose topic (e.g. AMCL)", "tf": "TF map → base_link"}


def _wide() -> dict[str, Any]:
    """Fresh style/layout kwargs (a Layout shared by several widgets breaks their rendering)."""
    return {
        "style": {"description_width": "200px"},
        "layout": w.Layout(width="100%", max_width="720px", height=f"{TOUCH_PX - 8}px"),
    }


def _combobox(value: str, label: str, css_class: str) -> w.Combobox:
    box = w.Combobox(value=value, options=[], description=label, ensure_option=False, **_wide())
    box.add_class(css_class)
    return box


def _link_loss_toggle() -> w.ToggleButtons:
    """Issue 24: what a goal does when the dashboard loses the chair (README: goal semantics)."""
    toggle = w.ToggleButtons(
        options=[("Let goals finish", "finish"), ("Cancel them", "cancel")],
        value="finish",
        style={"button_width": "160px"},
    )
    toggle.add_class("pmk-settings-goals-on-link-loss")
    return toggle


def _parse_number(field: str, raw: str) -> float:
    try:
        return float(raw.strip().replace(",", "."))
    except ValueError:
        raise SettingsError(f"{field}: invalid value {raw!r}: give a number, e.g. 0.5", field=field) from None


def _parse_port(field: str, raw: object) -> int:
    try:
        port = int(str(raw).strip())
    except ValueError:
        raise SettingsError(
            f"{field}: invalid value {raw!r}: give a port number between 1 and 65535", field=field
        ) from None
    return port


def _form_fields() -> dict[str, w.Widget]:
    """The form's inputs by profile field (text values, parsed in ``form_profile``)."""
    fields: dict[str, w.Widget] = {
        "name": text("", "Wheelchair name", "pmk-settings-name"),
        "host": text("", "Wheelchair IP / host", "pmk-settings-host", placeholder="192.168.1.20"),
        "port": text("9090", "rosbridge port", "pmk-settings-port"),
        "tls": w.ToggleButtons(
            options=[("ws (plain)", "False"), ("wss (TLS)", "True")], value="False", description="rosbridge over"
        ),
        "tls_ca_file": text("", "TLS CA file (else pin)", "pmk-settings-tls-ca", placeholder="empty: pin"),
        "odom_topic": _combobox("/odom", "Odometry topic", "pmk-settings-odom"),
        "scan_topic": _combobox("/scan", "Laser topic", "pmk-settings-scan"),
        "pose_source": w.Dropdown(
            options=[(_POSE_LABELS[s], s) for s in POSE_SOURCES],
            value="odometry",
            description="Position from",
            **_wide(),
        ),
        "pose_topic": _combobox("/amcl_pose", "Pose topic", "pmk-settings-pose-topic"),
        "ssh_user": text("", "SSH user", "pmk-settings-user"),
        "ssh_port": text("22", "SSH port", "pmk-settings-ssh-port"),
        "auth": w.ToggleButtons(
            options=list(AUTH_METHODS),
            value="password",
            style={"button_width": "140px"},
        ),
        "password": text("", "SSH password", "pmk-settings-password", password=True),
        "key_file": text("", "SSH key file", "pmk-settings-key", placeholder="~/.ssh/id_ed25519"),
        "remote_maps_dir": text("~/ALMA_MAPS", "Maps folder on chair", "pmk-settings-remote-dir"),
        "cmd_vel_topic": _combobox("/cmd_vel", "Drive commands topic", "pmk-settings-cmd-vel"),
        **{
            f: text(str(_DEFAULTS[f]), label, f"pmk-settings-{f.replace('_', '-')}")
            for f, label in DRIVE_NUMBERS.items()
        },
        # spoken feedback (pmk_nb/ui/common/speech_output.py); text values like the rest of the form
        "speech_on": w.ToggleButtons(options=[("Speak", "True"), ("Silent", "False")], value="True"),
        "speech_voice": text("en", "Voice (language code)", "pmk-settings-speech-voice", placeholder="en"),
        "speech_rate": text("1.0", "Speaking rate (1 = normal)", "pmk-settings-speech-rate"),
        "chair_width": text(f"{DEFAULT_CHAIR_WIDTH:g}", "Chair width (m), for map checks", "pmk-settings-chair-width"),
        "goals_on_link_loss": _link_loss_toggle(),
        # the rider's display (pmk_nb/ui/common/display_prefs.py): applied on the app root once saved
        "high_contrast": w.ToggleButtons(
            options=[("Standard", "False"), ("High contrast", "True")],
            value="False",
            description="Colours",
            style={"button_width": "170px"},
        ),
        "large_text": w.ToggleButtons(
            options=[("Standard", "False"), ("Large text", "True")],
            value="False",
            description="Text size",
            style={"button_width": "170px"},
        ),
        # where Home's joystick and Stop dock: the rider's hand (issue 28)
        "drive_hand": w.ToggleButtons(options=[("Right hand", "right"), ("Left hand", "left")], value="right"),
    }
    fields["drive_hand"].add_class("pmk-settings-drive-hand")
    fields["high_contrast"].add_class("pmk-settings-high-contrast")
    fields["large_text"].add_class("pmk-settings-large-text")
    fields["speech_on"].add_class("pmk-settings-speech-on")
    fields["tls"].add_class("pmk-settings-tls")
    fields["pose_source"].add_class("pmk-settings-pose-source")
    fields["auth"].add_class("pmk-settings-auth")
    return fields


#: Shown under "Connected" when the status comes from the page's own link rather than a test.
LIVE_LINK_NOTE = "This page is connected to the chair (Home's preview)."
LIVE_NOTE_HTML = f"<div class='pmk-status-reason'>{escape(LIVE_LINK_NOTE)}</div>"


def page_link_state(ctx: AppContext) -> str | None:
    """ "Connected" / "Connecting" when this kernel holds a link to the saved chair that is open or
    opening, else None. Looks only at links already made: showing Settings never connects."""
    import sys

    if "pmk_nb.chair.link.registry" not in sys.modules:  # no link was ever made in this kernel
        return None
    from pmk_nb.chair.link import LinkState, open_links

    profile = ctx.profile()
    if profile is None:
        return None
    for link in open_links():
        if (link.host, int(link.port)) != (profile.host, int(profile.port)):
            continue
        state = link.state
        if state in (LinkState.CONNECTED, LinkState.STALE):
            return "Connected"
        if state == LinkState.CONNECTING:
            return "Connecting"
    return None


class SettingsScreen:
    """The Settings screen; ``widget`` is its form, ``info_widget`` the connection status panel."""

    def __init__(self, ctx: AppContext) -> None:
        self.ctx = ctx
        self._test_lock = threading.Lock()
        self.state = "Disconnected"
        self.last_report: ConnectionReport | None = None
        self.profile_picker = w.Dropdown(options=[], description="Saved chairs", **_wide())
        self.profile_picker.add_class("pmk-settings-profile")
        self.profile_picker.observe(guard(ctx, "Loading a chair profile")(self._on_pick), names="value")
        self.fields = _form_fields()
        self.errors = {name: field_error() for name in self.fields}
        self.fields["auth"].observe(guard(ctx, "Choosing SSH login")(lambda _c: self._auth_visibility()), "value")
        self.save_button = button("Save", "pmk-settings-save", icon="save", style="primary")
        self.test_button = button("Test connection", "pmk-settings-test", icon="plug")
        self.save_button.on_click(guard(ctx, "Saving settings")(lambda _b: self.save()))
        self.test_button.on_click(guard(ctx, "Testing the connection")(lambda _b: self.test_connection()))
        self.message = w.HTML("")
        self.message.add_class("pmk-settings-message")
        self.status = w.HTML("")
        self.status.add_class("pmk-settings-status")
        self.map_info = w.HTML("")
        self.map_info.add_class("pmk-settings-mapinfo")
        self.cert_prompt = CertificatePrompt(ctx)  # a wss chair's first certificate (issue 24)
        self.info_widget = w.VBox([self.status, self.map_info])
        self.rows = {name: w.VBox([field, self.errors[name]]) for name, field in self.fields.items()}
        self._label_row("auth", "SSH login", "pmk-settings-auth")
        self._label_row("goals_on_link_loss", "When the dashboard loses the chair", "pmk-settings-loss")
        self._label_row("drive_hand", "Joystick at the side of", "pmk-settings-loss")
        actions = w.HBox([self.save_button, self.test_button])
        actions.add_class("pmk-row")
        self.widget = w.VBox(
            [
                heading("Wheelchair settings"),
                self.profile_picker,
                *self.rows.values(),
                actions,
                self.cert_prompt.widget,  # under Test connection, like the Maps screen's host key box
                self.message,
                pin_section(ctx),  # the kiosk PIN (pmk_nb/ui/kiosk/mode.py)
            ],
            layout=w.Layout(width="100%"),
        )
        self.widget.add_class("pmk-settings")
        self._set_state("Disconnected")
        self._reload_profiles()

    def _label_row(self, name: str, label: str, css: str = "") -> None:
        """A field with its label to the left (``css``-label and ``css``-row classes when given)."""
        head = w.HTML(label)
        row = w.HBox([head, self.fields[name]])
        if css:
            head.add_class(f"{css}-label")
            row.add_class(f"{css}-row")
        self.rows[name].children = (row, self.errors[name])

    # -- form <-> profile ------------------------------------------------------------------------------
    def _reload_profiles(self, select: str | None = None) -> None:
        try:
            names = self.ctx.profiles.names()
        except SettingsError as err:
            self.ctx.notify(str(err), "error")
            names = []
        current = self.ctx.profile()
        chosen = select or (current.name if current else None)
        self.profile_picker.options = names
        if chosen in names:
            self.profile_picker.value = chosen
            self.load(self.ctx.profiles.get(chosen))
        self.profile_picker.layout.display = "flex" if len(names) > 1 else "none"

    def _on_pick(self, change: dict[str, Any]) -> None:
        name = change.get("new")
        if isinstance(name, str) and name:
            self.load(self.ctx.profiles.get(name))

    def load(self, profile: ChairProfile) -> None:
        """Fill the form from a profile (the password is never shown, only whether one is stored)."""
        self._loaded = profile
        for name, field in self.fields.items():
            if name == "password":
                continue
            value = getattr(profile, name)
            field.value = "" if value is None else str(value)
        stored = self.ctx.ssh_password(profile)
        self.fields["password"].value = ""
        self.fields["password"].placeholder = "stored: leave empty to keep" if stored else ""
        for err in self.errors.values():
            err.value = ""
        self._auth_visibility()

    def _auth_visibility(self) -> None:
        key = self.fields["auth"].value == "key"
        self.rows["key_file"].layout.display = "flex" if key else "none"
        self.rows["password"].layout.display = "none" if key else "flex"

    def form_profile(self) -> ChairProfile:
        """The profile the form describes; raises SettingsError naming the first bad field."""
        values = {name: self.fields[name].value for name in self.fields if name != "password"}
        for name, value in values.items():
            if not isinstance(value, str):
                raise SettingsError(f"{name}: invalid value {value!r}: expected text", field=name)
        values = {k: v.strip() for k, v in values.items()}
        base = getattr(self, "_loaded", None)
        drive_numbers: dict[str, Any] = {f: _parse_number(f, values[f]) for f in DRIVE_NUMBERS}
        profile = ChairProfile(
            name=values["name"],
            host=values["host"],
            port=_parse_port("port", values["port"]),
            tls=values["tls"] == "True",
            tls_ca_file=values["tls_ca_file"] or None,
            odom_topic=values["odom_topic"],
            scan_topic=values["scan_topic"],
            pose_source=values["pose_source"],
            pose_topic=values["pose_topic"],
            ssh_user=values["ssh_user"],
            ssh_port=_parse_port("ssh_port", values["ssh_port"]),
            auth=values["auth"],
            key_file=values["key_file"] or None,
            remote_maps_dir=values["remote_maps_dir"],
            cmd_vel_topic=values["cmd_vel_topic"],
            **drive_numbers,
            speech_on=values["speech_on"] == "True",
            speech_voice=values["speech_voice"],
            speech_rate=_parse_number("speech_rate", values["speech_rate"]),
            chair_width=_parse_number("chair_width", values["chair_width"]),
            goals_on_link_loss=values["goals_on_link_loss"],
            high_contrast=values["high_contrast"] == "True",
            large_text=values["large_text"] == "True",
            drive_hand=values["drive_hand"],
        )
        if base is not None and base.name == profile.name:
            keep = {
                f: getattr(base, f)
                for f in (
                    "reload_service",
                    "reload_kind",
                    "footprint_radius",
                    "known_hosts",
                    "host_key_check",
                    "goal_accept_s",
                    "goal_quiet_s",
                    "plan_topic",
                    "bridge_secret_file",  # a classroom seat's chair secret (pmk hub): never on the form
                )
            }
            profile = dataclasses.replace(profile, **keep)
        profile.validate()
        return profile

    def _show_field_error(self, err: SettingsError, outcome: str) -> None:
        """The problem under its field (one place); the message line says what did not happen."""
        target = self.errors.get(err.field) if err.field is not None else None
        if target is not None:
            target.value = escape(err)
            said = f"{outcome}: correct the field marked in red."
        else:
            said = f"{outcome}: {err}"
        self.message.value = f"<span class='pmk-field-error'>{escape(said)}</span>"
        self.ctx.notify(said, "warning", inline=True)

    # -- actions -----------------------------------------------------------------------------------
    def _checked_form_profile(self, outcome: str) -> ChairProfile | None:
        """The form as a valid profile, or None with the first bad field's message shown under it.

        Each attempt starts clean: the previous attempt's messages ("Saved", "Not saved") go.
        """
        for err in self.errors.values():
            err.value = ""
        self.message.value = ""
        try:
            return self.form_profile()
        except SettingsError as err:
            self._show_field_error(err, outcome)
            return None

    @needs_pin("Saving settings")
    def save(self) -> ChairProfile | None:
        """Validate and save the form; it becomes the current chair. Returns None when invalid."""
        profile = self._checked_form_profile("Not saved")
        if profile is None:
            return None
        self.ctx.profiles.save(profile)
        password = self.fields["password"].value
        if profile.auth == "password" and isinstance(password, str) and password:
            self.ctx.profiles.set_password(profile, password)
        self.message.value = (
            f"Saved {escape(profile.name)}. Passwords are kept in {escape(self.ctx.profiles.password_storage)}."
        )
        self.ctx.notify(f"Saved settings for {profile.name}.", inline=True)
        self._reload_profiles(select=profile.name)
        return profile

    @needs_pin("Testing the connection")  # it connects wherever the form says
    def test_connection(self) -> Any:
        """Connect to the chair in the form (in a thread) and show status and published map info."""
        profile = self._checked_form_profile("Not tested")
        if profile is None:
            return None
        self._set_state("Connecting")
        self.map_info.value = ""
        self.cert_prompt.box.hide()

        def work() -> tuple[ConnectionReport, dict[str, list[str]]]:
            from pmk_nb.chair.link import ChairLink

            link = ChairLink(profile.host, profile.port, **profile.link_options())
            try:
                report = link.test_connection(timeout=TEST_TIMEOUT)
                found: dict[str, list[str]] = {}
                if report.ok and report.rosapi is not False:  # no rosapi: nothing to list (report.notes)
                    for field, types in TOPIC_TYPES.items():
                        found[field] = sorted({t for typ in types for t in link.topics_of_type(typ)})
                return report, found
            finally:
                link.close()

        def done(result: tuple[ConnectionReport, dict[str, list[str]]]) -> None:
            report, found = result
            self.last_report = report
            if not report.ok:
                self.cert_prompt.ask(report.error, self.test_connection)  # shown for an unknown certificate only
                self._set_state("Failed", report.reason)
                return
            self._set_state("Connected")
            info = report.map_info
            if info is not None:
                self.map_info.value = (
                    f"<div>Map width: <b>{info.width}</b></div><div>Map height: <b>{info.height}</b></div>"
                    f"<div>Resolution: <b>{info.resolution:g} m</b></div>"
                )
            else:
                self.map_info.value = "<div>The chair publishes no map yet.</div>"
            self.map_info.value += "".join(f"<div class='pmk-note'>{escape(note)}</div>" for note in report.notes)
            for field, topics in found.items():
                self.fields[field].options = topics

        def failed(err: BaseException) -> None:
            # a typed error is already in words; anything else is named, never a bare "'infos'"
            self._set_state("Failed", str(err) if isinstance(err, PmkError) else error_text(err, "Connecting"))

        return run_in_thread(
            self.ctx,
            "Testing the connection",
            work,
            on_done=done,
            on_error=failed,
            busy=[self.test_button],
            exclusive=self._test_lock,
        )

    def on_show(self) -> None:
        """Shown: the status says whether this page holds a live link to the saved chair (Home's
        preview connected it), instead of "Disconnected" from before any test (issue 29)."""
        if self._test_lock.locked():  # a test is running: its outcome will be shown
            return
        live = page_link_state(self.ctx)
        if live is not None:
            self._set_state(live, LIVE_LINK_NOTE, quiet=True)
        elif self.state == "Connected" and self.status.value.endswith(LIVE_NOTE_HTML):
            self._set_state("Disconnected", quiet=True)  # the live link has gone since

    def _set_state(self, state: str, reason: str = "", *, quiet: bool = False) -> None:
        self.state = state
        colour = {"Connected": "#a5d6a7", "Failed": "#ff8a80", "Connecting": "#ffe082"}.get(state, "#eceff1")
        shown = "Disconnected" if state == "Failed" else state
        extra = f"<div class='pmk-status-reason'>{escape(reason)}</div>" if reason else ""
        self.status.value = f"<div>Status: <b style='color:{colour}'>{shown}</b></div>{extra}"
        # the status above is the one place for the test's outcome; the app's line only clears
        if quiet:
            return
        if state == "Failed":
            self.ctx.notify(f"Connection failed: {reason}", "error", inline=True)
        elif state == "Connected":
            self.ctx.notify("Connected.", inline=True)

    def close(self) -> None:
        self.widget.close()
