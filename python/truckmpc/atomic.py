"""Writing files so that readers never see half of one.

`atomic_write_text` replaces a single file in one step. `OutputDir` stages a whole set of output
files and publishes them together only if the block that wrote them finished without an exception,
so an interrupted or failed run leaves the previous results (or nothing) in place, never a mix.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path
from types import TracebackType

__all__ = ["OutputDir", "atomic_write_text"]


def atomic_write_text(path: str | os.PathLike[str], text: str, encoding: str = "utf-8") -> None:
    """Write `text` to `path` atomically: a temporary file in the same directory is written, synced
    to disk and renamed over `path`. Line endings are written exactly as given."""
    path = Path(path)
    fd, tmp_name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding=encoding, newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(tmp_name, _mode_for(path))
        os.replace(tmp_name, path)
    except BaseException as err:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        if isinstance(err, OSError) and err.filename == tmp_name:  # name the file, not its temporary
            raise OSError(err.errno, err.strerror, str(path)) from None
        raise
    _fsync_dir(path.parent)


class OutputDir:
    """Stage output files and publish them into `out_dir` together.

    `with OutputDir(out_dir) as staging:` yields a fresh temporary directory created beside
    `out_dir` (same file system, so the final moves are renames). On normal exit every file written
    under `staging` is moved into `out_dir` (created if missing; files of the same name replaced;
    other files already there left alone), or, with `replace=True`, the staging directory takes the
    place of `out_dir` whole, so no file of an earlier output survives beside the new one. On an
    exception the staging directory is deleted and `out_dir` is not touched. The staging directory
    is removed in both cases. An error while writing names the file in `out_dir`, never the
    staging directory.
    """

    def __init__(self, out_dir: str | os.PathLike[str], replace: bool = False) -> None:
        self.out_dir = Path(out_dir)
        self.replace = replace
        self._staging: Path | None = None

    def __enter__(self) -> Path:
        parent = self.out_dir.resolve().parent
        parent.mkdir(parents=True, exist_ok=True)
        self._staging = Path(tempfile.mkdtemp(dir=parent, prefix=f".{self.out_dir.resolve().name}.staging-"))
        return self._staging

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        staging, self._staging = self._staging, None
        if staging is None:
            return
        try:
            if exc_type is None and self.replace:
                _swap_in(staging, self.out_dir)
            elif exc_type is None:
                _publish(staging, self.out_dir)
            elif isinstance(exc, OSError) and exc.filename and str(staging) in str(exc.filename):
                named = self.out_dir / Path(exc.filename).relative_to(staging)
                raise OSError(exc.errno, exc.strerror, str(named)) from None
        finally:
            shutil.rmtree(staging, ignore_errors=True)


def _swap_in(staging: Path, out_dir: Path) -> None:
    """Put `staging` in the place of `out_dir` (two renames; the old directory is then deleted)."""
    for source in staging.rglob("*"):
        if source.is_file() and not source.is_symlink():
            _fsync_file(source)
    old = None
    if out_dir.exists():
        old = Path(tempfile.mkdtemp(dir=out_dir.resolve().parent, prefix=f".{out_dir.resolve().name}.old-"))
        os.replace(out_dir, old / "previous")
    staging.chmod(_mode_for_dir(out_dir if old is None else old / "previous"))
    os.replace(staging, out_dir)
    _fsync_dir(out_dir.resolve().parent)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def _publish(staging: Path, out_dir: Path) -> None:
    """Move every file under `staging` to the same relative place under `out_dir`."""
    out_dir.mkdir(parents=True, exist_ok=True)
    for source in sorted(staging.rglob("*")):
        target = out_dir / source.relative_to(staging)
        if source.is_dir() and not source.is_symlink():
            target.mkdir(parents=True, exist_ok=True)
            continue
        if source.is_file() and not source.is_symlink():
            _fsync_file(source)
        os.replace(source, target)
    _fsync_dir(out_dir)


def _mode_for(path: Path) -> int:
    """Permission bits for a replacement of `path`: those of the existing file, else 0o666 less umask
    (mkstemp creates files readable by the owner only)."""
    try:
        return path.stat().st_mode & 0o7777
    except FileNotFoundError:
        umask = os.umask(0o022)
        os.umask(umask)
        return 0o666 & ~umask


def _mode_for_dir(previous: Path) -> int:
    """Permission bits for a replacement directory: those of the one it replaces, else 0o777 less
    umask (mkdtemp creates directories for the owner only)."""
    try:
        return previous.stat().st_mode & 0o7777
    except FileNotFoundError:
        umask = os.umask(0o022)
        os.umask(umask)
        return 0o777 & ~umask


def _fsync_file(path: Path) -> None:
    with open(path, "rb") as handle:
        os.fsync(handle.fileno())


def _fsync_dir(path: Path) -> None:
    """Make a rename inside `path` durable (POSIX only; a no-op where directories can't be opened)."""
    with contextlib.suppress(OSError):
        fd = os.open(path, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
