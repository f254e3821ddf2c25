"""The package's one atomic file writer, and its one guarded reader.

Every file the package writes (results, networks, figures) goes through :func:`atomic_write`:
a temporary file in the target's folder, written, flushed and fsynced, given one file mode,
renamed over the target, and the folder fsynced. A reader sees the old file or the new one,
never half of one; a crash (even ``kill -9``) leaves at most a temporary file named
``.<target>.<pid>.<random>.tmp``, which :func:`remove_stale_temporaries` cleans up once its
writer is gone.

Every file the package reads from a store or a ledger (results, tables, manifests) goes
through :func:`read_regular`: it opens the path without blocking, refuses anything but a
regular file (a FIFO, a device, a folder) and a file outside the folder it must lie in (a
symlink out of it, a name with ``..``), and refuses a file larger than the reader's bound,
each *before* reading a byte of it.
"""

from __future__ import annotations

import os
import re
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

__all__ = [
    "UnsafeFile",
    "atomic_write",
    "default_mode",
    "read_regular",
    "remove_stale_temporaries",
]


class UnsafeFile(ValueError):
    """A file :func:`read_regular` refuses to read: not a regular file, outside its folder,
    or larger than its bound."""


#: What :func:`read_regular` calls a file of each kind it refuses.
_KINDS = (
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISSOCK, "a socket"),
)


def read_regular(path, limit: int, within=None) -> bytes:
    """The bytes of ``path``: a regular file of at most ``limit`` bytes, lying inside the
    folder ``within`` (if given; symlinks resolved). :class:`UnsafeFile` naming the path and
    what it is otherwise, decided before any byte is read (a FIFO is opened without blocking
    and never read); ``OSError`` if it cannot be opened."""
    path = Path(path)
    if within is not None:
        folder = Path(within).resolve()
        if not path.resolve().is_relative_to(folder):
            raise UnsafeFile(f"{path} lies outside {folder}: not read")
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    try:
        found = os.fstat(fd)
        for test, kind in _KINDS:
            if test(found.st_mode):
                raise UnsafeFile(f"{path} is {kind}, not a regular file: not read")
        if not stat.S_ISREG(found.st_mode):
            raise UnsafeFile(f"{path} is not a regular file: not read")
        if found.st_size > limit:
            raise UnsafeFile(f"{path} holds {found.st_size} bytes, at most {limit}: not read")
        with os.fdopen(os.dup(fd), "rb") as f:
            data = f.read(limit + 1)
    finally:
        os.close(fd)
    if len(data) > limit:  # it grew while it was read
        raise UnsafeFile(f"{path} holds more than {limit} bytes: not read")
    return data


def default_mode() -> int:
    """The mode of an ordinary new file: ``0o666`` less the process's umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write(path, write: Callable[[BinaryIO], None], mode: int | None = None) -> Path:
    """Write ``path`` atomically: ``write(f)`` fills a temporary file in the same folder,
    which is flushed, fsynced, given ``mode`` (default :func:`default_mode`) and renamed over
    ``path``. The folder is created if missing. Returns ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.name}.{os.getpid()}.", suffix=".tmp", dir=path.parent
    )
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, default_mode() if mode is None else mode)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    _fsync_folder(path.parent)
    return path


def _fsync_folder(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:  # some platforms cannot open folders
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def remove_stale_temporaries(path) -> list[Path]:
    """Delete the temporary files that earlier writers of ``path`` left behind (their process
    is gone, e.g. killed during a save). Returns the deleted files."""
    path = Path(path)
    pattern = re.compile(re.escape(f".{path.name}.") + r"(\d+)\..*\.tmp")
    removed = []
    if not path.parent.is_dir():
        return removed
    for candidate in path.parent.iterdir():
        match = pattern.fullmatch(candidate.name)
        if match and not _alive(int(match.group(1))):
            try:
                candidate.unlink()
                removed.append(candidate)
            except FileNotFoundError:
                pass
    return removed
