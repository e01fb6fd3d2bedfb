"""Reading TOML files and writing output files atomically: the file handling every layer shares.

An output file is first written next to its destination under a temporary name and then renamed
over it (``os.replace``), so a reader never sees a half-written file and an interrupted run
leaves the previous file intact.
"""

from __future__ import annotations

import os
import tempfile
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

from scalf_opt.errors import ConfigError

MAX_TOML_BYTES = 1024 * 1024
"""Largest configuration file read [bytes]; real ones are a few kB."""


def read_toml(path: Path, kind: str) -> dict[str, Any]:
    """Parse ``path``; ``kind`` names the file in messages (``gait``, ``actuator``).

    Raises:
        ConfigError: The file cannot be read, is larger than :data:`MAX_TOML_BYTES`, is not
            UTF-8 text or not valid TOML (the message names the file).
    """
    try:
        if path.stat().st_size > MAX_TOML_BYTES:
            raise ConfigError(f"{path}: {kind} file larger than the {MAX_TOML_BYTES} bytes allowed")
        return tomllib.loads(path.read_bytes().decode("utf-8"))
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read {kind} file ({exc.strerror})") from exc
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: {kind} file is not UTF-8 text (byte {exc.start})") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from exc


def temporary_sibling(path: Path) -> tuple[int, str]:
    """Open a temporary file beside ``path`` with the permissions a new file would get.

    ``mkstemp`` creates files readable by their owner only; outputs should be as readable as any
    file the user creates, so the mode follows the umask.

    Raises:
        ConfigError: The directory cannot be created or written.
    """
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise ConfigError(f"{path.parent}: cannot write output directory ({exc.strerror})") from exc
    umask = os.umask(0)
    os.umask(umask)
    os.fchmod(fd, 0o666 & ~umask)
    return fd, tmp


def write_with(path: str | Path, write: Callable[[IO[bytes]], None]) -> Path:
    """Write ``path`` atomically: ``write`` fills a temporary sibling, which is then renamed."""
    path = Path(path)
    fd, tmp = temporary_sibling(path)
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def write_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    data = text.encode("utf-8")

    def write(handle: IO[bytes]) -> None:
        handle.write(data)

    return write_with(path, write)
