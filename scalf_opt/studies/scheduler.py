"""A Dask scheduler's address, checked before Dask's client is given it.

Dask's client trusts what answers at an address: a server that accepts the connection and never
answers held it past its own timeout, an HTTP server's answer read as a frame length asked for
3 EiB, and a ``tls://`` or ``ucx://`` address ended in a traceback. Here the address is parsed
(``tcp://host:port``, or ``host:port``; Dask's port 8786 when none is given) and probed: a Dask
scheduler speaks first, a handshake whose first 8 bytes are its length (little-endian), so the
probe waits at most :data:`PROBE_TIMEOUT_S` for those bytes and checks that the length is one a
handshake has.
"""

from __future__ import annotations

import socket
import struct
from urllib.parse import urlsplit

from scalf_opt.errors import ConfigError

DASK_PORT = 8786
"""Dask's default scheduler port."""

PROBE_TIMEOUT_S = 10.0
"""How long the probe waits to connect, and then for the scheduler's first bytes [s]."""

MAX_HANDSHAKE_BYTES = 1024 * 1024
"""Largest handshake a scheduler may announce [bytes] (Dask's: a few hundred)."""


def scheduler_endpoint(address: str) -> tuple[str, int]:
    """``(host, port)`` of a scheduler address; only plain TCP is taken.

    Raises:
        ConfigError: Another protocol (``tls://`` needs the cluster's certificates, which
            scalf-opt does not take; ``ucx://`` and others need libraries it does not install),
            no host, or a port that is not a number from 1 to 65535.
    """
    text = address.strip()
    scheme, _, rest = text.rpartition("://")
    if scheme and scheme != "tcp":
        raise ConfigError(
            f"--scheduler {address[:200]}: only tcp:// addresses are taken (a {scheme[:20]}:// "
            "scheduler needs settings scalf-opt does not take; reach it through a tcp:// "
            "address, e.g. an SSH tunnel)"
        )
    try:
        parts = urlsplit(f"tcp://{rest}")
        port = parts.port or DASK_PORT
    except ValueError:
        raise ConfigError(
            f"--scheduler {address[:200]}: the port must be a number from 1 to 65535"
        ) from None
    if not parts.hostname or parts.path not in ("", "/") or parts.query or parts.username:
        raise ConfigError(f"--scheduler {address[:200]}: expected tcp://HOST:PORT")
    if port == 0:
        raise ConfigError(f"--scheduler {address[:200]}: the port must be from 1 to 65535")
    return parts.hostname, port


def check_scheduler(address: str, timeout_s: float = PROBE_TIMEOUT_S) -> str:
    """The address Dask is given (``tcp://host:port``), once a Dask scheduler answered there.

    Raises:
        ConfigError: The address is not taken (:func:`scheduler_endpoint`), nothing listens, the
            server does not speak within ``timeout_s``, or it speaks another protocol.
    """
    host, port = scheduler_endpoint(address)
    shown = f"--scheduler {address[:200]}"
    try:
        with socket.create_connection((host, port), timeout=timeout_s) as probe:
            first = _receive(probe, 8)
    except TimeoutError:
        raise ConfigError(
            f"{shown}: it did not answer within {timeout_s:g} s (not a Dask scheduler, or busy)"
        ) from None
    except OSError as exc:
        reason = exc.strerror or str(exc) or type(exc).__name__
        raise ConfigError(f"{shown}: cannot reach the Dask scheduler ({reason})") from None
    (length,) = struct.unpack("<Q", first) if len(first) == 8 else (0,)
    if not 0 < length <= MAX_HANDSHAKE_BYTES:
        raise ConfigError(f"{shown}: what answers there does not speak Dask's protocol")
    bracket = f"[{host}]" if ":" in host else host
    return f"tcp://{bracket}:{port}"


def _receive(connection: socket.socket, count: int) -> bytes:
    """Up to ``count`` bytes, fewer if the server closes the connection first."""
    data = b""
    while len(data) < count:
        piece = connection.recv(count - len(data))
        if not piece:
            break
        data += piece
    return data
