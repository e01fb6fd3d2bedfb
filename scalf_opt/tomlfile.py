"""Read a TOML configuration file, turning every failure into a one-line :class:`ConfigError`."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from scalf_opt.errors import ConfigError


def read_toml(path: Path, kind: str) -> dict[str, Any]:
    """Parse ``path``; ``kind`` names the file in messages (``gait``, ``actuator``).

    Raises:
        ConfigError: The file cannot be read or is not valid TOML (the message names the file).
    """
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read {kind} file ({exc.strerror})") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from exc
