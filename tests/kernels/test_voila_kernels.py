"""The dashboard's kernel manager against real kernels: what a kernel says on IOPub decides when it ends."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable
from pathlib import Path

from pmk_nb.serve.voila_kernels import FIRST_PAGE_WITHIN, RENDERED_PAGE_WITHIN, PageBoundKernelManager


async def _until(condition: Callable[[], bool], what: str, timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"timed out after {timeout:.0f} s waiting for {what}"
        await asyncio.sleep(0.05)


def _with_kernel(tmp_path: Path, scenario: Callable[[PageBoundKernelManager, str, object], Awaitable[None]]) -> None:
    async def run() -> None:
        manager = PageBoundKernelManager(root_dir=str(tmp_path))
        kernel_id = await manager.start_kernel(kernel_name="python3")
        client = manager.get_kernel(kernel_id).client()
        client.start_channels()
        try:
            await client.wait_for_ready(timeout=60)
            await scenario(manager, kernel_id, client)
        finally:
            client.stop_channels()
            await manager.shutdown_all(now=True)
            if manager._checker is not None:
                manager._checker.stop()

    asyncio.run(run())


def test_a_kernel_whose_page_never_connected_ends_soon_after_voila_ran_it(tmp_path: Path) -> None:
    """A page closed while it loaded: its kernel goes a grace after Voilà's run, not 120 s after its start."""

    async def scenario(manager: PageBoundKernelManager, kid: str, voila: object) -> None:
        started = time.monotonic()
        assert kid not in manager.orphans(started + RENDERED_PAGE_WITHIN + 1)
        # what Voilà's executor does: run the cells with its own client, then stop that client
        msg_id = voila.execute("import time; time.sleep(0.5); x = 1")  # type: ignore[attr-defined]
        while (await voila.get_shell_msg(timeout=30))["parent_header"].get("msg_id") != msg_id:  # type: ignore[attr-defined]
            pass
        await asyncio.sleep(0.5)
        assert kid not in manager._rendered_at, "the cells ran, but Voilà has not sent the page's HTML yet"
        assert kid not in manager.orphans(time.monotonic() + RENDERED_PAGE_WITHIN + 1)
        voila.stop_channels()  # type: ignore[attr-defined]
        assert kid in manager._rendered_at
        rendered = manager._rendered_at[kid]
        assert rendered >= started + 0.5
        assert kid not in manager.orphans(rendered + RENDERED_PAGE_WITHIN - 1), "its page may still be loading"
        assert kid in manager.orphans(rendered + RENDERED_PAGE_WITHIN + 1), "no page came after the render"
        assert RENDERED_PAGE_WITHIN < FIRST_PAGE_WITHIN / 4

        manager.notify_connect(kid)  # the page's websocket arrives in time
        assert kid not in manager._rendered_at and kid not in manager.orphans(rendered + FIRST_PAGE_WITHIN + 1)
        manager.notify_disconnect(kid)
        assert kid in manager.orphans(time.monotonic() + 5), "a page that came and went: the short grace"

    _with_kernel(tmp_path, scenario)


def test_the_kernel_that_says_its_page_is_gone_is_shut_down_by_the_server(tmp_path: Path) -> None:
    """The kernel's watchdog message travels over real IOPub to the manager, which ends the kernel."""

    async def scenario(manager: PageBoundKernelManager, kid: str, client: object) -> None:
        manager.notify_connect(kid)  # a page is connected: only the message can end this kernel
        client.execute(  # type: ignore[attr-defined]
            "from pmk_nb.ui.common.page_lifecycle import tell_server_page_gone\ntell_server_page_gone()"
        )
        await _until(lambda: kid not in manager, "the kernel's shutdown after its page-gone message", timeout=60)
        assert kid not in manager._alone_since and kid not in manager._gone_streams

    _with_kernel(tmp_path, scenario)


def test_the_render_grace_grows_while_pages_load_slowly() -> None:
    """make soak: loaded pages connected up to 14 s after the render; a fixed 20 s ended some still loading."""
    from pmk_nb.serve.voila_kernels import CONNECT_MEMORY, SLOW_CONNECT_FACTOR

    manager = PageBoundKernelManager()
    t = time.monotonic()
    assert manager.render_grace(t) == RENDERED_PAGE_WITHIN, "no page seen yet: the floor"
    manager._alone_since["k"] = t - 10.0
    manager._rendered_at["k"] = t - 5.0
    manager.notify_connect("k")  # connected 5 s after the render: still the floor (3 x 5 < 20)
    assert [round(w) for _, w in manager._connect_waits] == [5] and manager.render_grace(t) == RENDERED_PAGE_WITHIN
    manager._connect_waits.append((t, 14.0))
    assert manager.render_grace(t) == SLOW_CONNECT_FACTOR * 14.0
    manager._alone_since["slow"] = t
    manager._rendered_at["slow"] = t + 10.0
    assert "slow" not in manager.orphans(t + 10.0 + 30.0), "30 s after the render, within the slow pages' grace"
    assert "slow" in manager.orphans(t + 10.0 + SLOW_CONNECT_FACTOR * 14.0 + 1)
    assert manager.render_grace(t + CONNECT_MEMORY + 1) == RENDERED_PAGE_WITHIN, "slow pages are forgotten"
    manager._connect_waits.append((t, 100.0))
    assert manager.render_grace(t) == FIRST_PAGE_WITHIN, "never past the limit for every kernel"


def test_a_kernel_is_not_culled_while_voila_still_renders_its_page() -> None:
    """Classroom soak at load 26: a page's render (its kernel starts its own chair) ran past a fixed
    120 s from the kernel's start and its kernel was ended before the page could connect."""
    from pmk_nb.serve.voila_kernels import RENDERING_LIMIT

    manager = PageBoundKernelManager()
    t = time.monotonic()
    manager._alone_since["k"] = t  # started, Voilà runs its notebook
    assert "k" not in manager.orphans(t + FIRST_PAGE_WITHIN + 60), "still rendering: its page is waiting"
    assert "k" in manager.orphans(t + RENDERING_LIMIT + 1), "a render that never ends is taken for stuck"


def test_a_page_rendered_slowly_gets_as_long_to_connect() -> None:
    """A page whose render took 80 s on a loaded machine loads its scripts slowly too: not ended 20 s on."""
    manager = PageBoundKernelManager()
    t = time.monotonic()
    manager._alone_since["k"] = t
    manager._rendered_at["k"], manager._render_took["k"] = t + 80.0, 80.0
    assert "k" not in manager.orphans(t + 80.0 + RENDERED_PAGE_WITHIN + 30), "within its own render time"
    assert "k" in manager.orphans(t + 80.0 + 81.0)
    manager._rendered_at["k"], manager._render_took["k"] = t + 2.0, 2.0  # a quick render: the floor
    assert "k" in manager.orphans(t + 2.0 + RENDERED_PAGE_WITHIN + 1)


def test_a_socket_closed_without_the_pages_goodbye_may_reconnect() -> None:
    """A live page on a starved machine answered the server's websocket ping late: the server closed its
    socket (no close code from the page), the page reconnected 3 s later to a kernel already ended."""
    from pmk_nb.serve.voila_kernels import PAGE_GRACE, RECONNECT_GRACE

    manager = PageBoundKernelManager()
    t = time.monotonic()
    for kid, code in (("dropped", None), ("closed", 1001)):
        manager._alone_since[kid] = t - 10.0
        manager.notify_connect(kid)
        manager.socket_closed(kid, code)
        manager._alone_since[kid] = t  # what notify_disconnect records (no real socket here)
    assert manager.orphans(t + PAGE_GRACE + 1) == ["closed"], "the page that closed goes after the short grace"
    assert "dropped" not in manager.orphans(t + PAGE_GRACE + 5)
    assert "dropped" in manager.orphans(t + RECONNECT_GRACE + 1)
    manager.notify_connect("dropped")  # it came back
    assert "dropped" not in manager.orphans(t + RECONNECT_GRACE + 60)
