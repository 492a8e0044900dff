"""How many simulated chairs a class may run at once, counted across every kernel of the class.

One more chair than the machine can simulate slows every page (each chair is a 20 Hz physics loop,
a laser and a rosbridge server inside its page's kernel), so the next page is refused with a clear
message instead.  The default cap (:func:`default_max_chairs`)::

    max(1, min(PAGES_PER_CORE * cores, (MEMORY_SHARE * total memory) // MIB_PER_PAGE))

with ``PAGES_PER_CORE = 5`` (issue 26: ten classroom pages on two cores) and ``MIB_PER_PAGE = 300``
(a classroom kernel and its chair, measured: see the README's sizing notes) of three quarters of the
memory; ``--max-chairs N`` overrides it.

The live chairs are a JSON file (``chairs.json`` in the class's state folder, pid -> ports) that
kernels change under an ``flock`` of ``chairs.lock``; a kernel removes its entry when it ends, and
entries of pids that no longer run are ignored and dropped (a killed kernel leaves no seat taken).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
from collections.abc import Iterator
from pathlib import Path

from pmk_nb.clock import WALL, Clock
from pmk_nb.errors import PmkError
from pmk_nb.fileio import atomic_write

PAGES_PER_CORE = 5
MIB_PER_PAGE = 300
MEMORY_SHARE = 0.75
CHAIRS_FILE = "chairs.json"
LOCK_FILE = "chairs.lock"


class ClassroomFull(PmkError):
    """Every chair of the class is taken: this page gets none.

    Attributes:
        in_use: chairs running now (their kernels alive).
        max_chairs: the cap.
    """

    def __init__(self, *, in_use: int, max_chairs: int) -> None:
        super().__init__(
            f"The class is full: {in_use} of {max_chairs} simulated chairs are in use, and one more would "
            "slow every page down.",
            hint="Close a page you no longer use, or ask the teacher to restart with a higher --max-chairs.",
        )
        self.in_use, self.max_chairs = in_use, max_chairs


def total_memory() -> int:
    """This machine's memory in bytes (0 when the system does not say)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError):
        return 0


def default_max_chairs(cores: int | None = None, memory: int | None = None) -> int:
    """The cap from the machine's cores and memory (formula in the module's docstring)."""
    cores = cores if cores is not None else (os.cpu_count() or 1)
    memory = memory if memory is not None else total_memory()
    by_cpu = PAGES_PER_CORE * max(1, cores)
    by_memory = int(MEMORY_SHARE * memory) // (MIB_PER_PAGE * 1024 * 1024) if memory > 0 else by_cpu
    return max(1, min(by_cpu, by_memory))


def pid_alive(pid: int) -> bool:
    """Whether a process ``pid`` runs (another user's counts as running)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


class ChairCap:
    """The class's live chairs, shared by its kernels through ``state_dir``.

    Args:
        state_dir: the class's state folder (``chairs.json`` and its lock).
        max_chairs: the cap.
        clock: a seat's ``since`` (wall seconds: other kernels and ``pmk hub`` read it); a
            ``VirtualClock`` in tests.
    """

    def __init__(self, state_dir: Path, max_chairs: int, *, clock: Clock = WALL) -> None:
        if max_chairs < 1:
            raise ValueError(f"max_chairs must be at least 1, not {max_chairs}")
        self.folder = Path(state_dir)
        self.max_chairs = int(max_chairs)
        self.path = self.folder / CHAIRS_FILE
        self.clock = clock

    @contextlib.contextmanager
    def _locked(self) -> Iterator[dict[str, dict[str, object]]]:
        """The live entries (dead pids dropped), written back when the block ends; under the lock."""
        self.folder.mkdir(parents=True, exist_ok=True)
        with open(self.folder / LOCK_FILE, "a+b") as lock:
            fcntl.flock(lock.fileno(), fcntl.LOCK_EX)
            try:
                entries = {pid: e for pid, e in self._read().items() if pid.isdigit() and pid_alive(int(pid))}
                yield entries
                atomic_write(self.path, json.dumps(entries, indent=1) + "\n", mode=0o644)
            finally:
                fcntl.flock(lock.fileno(), fcntl.LOCK_UN)

    def _read(self) -> dict[str, dict[str, object]]:
        try:
            raw = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}  # none yet, or a torn file from a crashed writer: start again from the live kernels
        return {str(k): v for k, v in raw.items() if isinstance(v, dict)} if isinstance(raw, dict) else {}

    def take(self, pid: int | None = None) -> None:
        """Hold a seat for ``pid`` (this process by default); a pid that holds one keeps it.

        Raises:
            ClassroomFull: ``max_chairs`` live kernels hold one already.
        """
        key = str(pid if pid is not None else os.getpid())
        with self._locked() as entries:
            if key not in entries and len(entries) >= self.max_chairs:
                raise ClassroomFull(in_use=len(entries), max_chairs=self.max_chairs)
            entries.setdefault(key, {"since": self.clock.now()})

    def note(self, pid: int | None = None, **facts: object) -> None:
        """Add facts (the chair's ports) to ``pid``'s seat: ``pmk hub`` and tests read them."""
        key = str(pid if pid is not None else os.getpid())
        with self._locked() as entries:
            if key in entries:
                entries[key].update(facts)

    def release(self, pid: int | None = None) -> None:
        """Give ``pid``'s seat back (nothing happens when it holds none)."""
        key = str(pid if pid is not None else os.getpid())
        with self._locked() as entries:
            entries.pop(key, None)

    def live(self) -> dict[int, dict[str, object]]:
        """The seats of live kernels: pid -> facts."""
        with self._locked() as entries:
            return {int(pid): dict(e) for pid, e in entries.items()}
