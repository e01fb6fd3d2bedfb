"""A Dask scheduler's address is parsed and probed before Dask's client is given it: what is
not a scheduler is refused in one line, within the probe's timeout, without a traceback."""

import socket
import threading

import pytest

from scalf_opt.errors import ConfigError
from scalf_opt.studies.scheduler import check_scheduler, scheduler_endpoint


@pytest.mark.parametrize(
    ("address", "endpoint"),
    [
        ("tcp://10.0.0.2:9000", ("10.0.0.2", 9000)),
        ("cluster.lab:9000", ("cluster.lab", 9000)),
        ("tcp://cluster.lab", ("cluster.lab", 8786)),
        ("tcp://[::1]:9000", ("::1", 9000)),
    ],
)
def test_a_tcp_address_is_taken(address, endpoint):
    assert scheduler_endpoint(address) == endpoint


@pytest.mark.parametrize(
    ("address", "message"),
    [
        ("tls://cluster.lab:8786", "only tcp:// addresses are taken .a tls:// scheduler"),
        ("ucx://cluster.lab:8786", "only tcp:// addresses are taken .a ucx:// scheduler"),
        ("tcp://cluster.lab:99999", "the port must be a number from 1 to 65535"),
        ("tcp://cluster.lab:port", "the port must be a number from 1 to 65535"),
        ("tcp://:8786", "expected tcp://HOST:PORT"),
        ("tcp://cluster.lab:8786/path", "expected tcp://HOST:PORT"),
    ],
)
def test_an_address_that_is_not_plain_tcp_is_refused(address, message):
    with pytest.raises(ConfigError, match=f"--scheduler {address}: {message}"):
        scheduler_endpoint(address)


def _server(answer: bytes | None):
    """A local server that answers ``answer`` at once on each connection (``None``: silence)."""
    listener = socket.create_server(("127.0.0.1", 0))
    held = []

    def serve():
        while True:
            try:
                connection, _ = listener.accept()
            except OSError:
                return
            held.append(connection)
            if answer is not None:
                connection.sendall(answer)

    threading.Thread(target=serve, daemon=True).start()
    return listener, f"tcp://127.0.0.1:{listener.getsockname()[1]}"


@pytest.mark.parametrize(
    ("answer", "message"),
    [
        (None, "it did not answer within 0.3 s"),
        (b"HTTP/1.1 400 Bad Request\r\n\r\n", "what answers there does not speak Dask's protocol"),
        (b"\x00" * 8, "what answers there does not speak Dask's protocol"),
    ],
    ids=["silent", "http", "empty handshake"],
)
def test_a_server_that_is_not_a_scheduler_is_refused(answer, message):
    listener, address = _server(answer)
    with listener, pytest.raises(ConfigError, match=message):
        check_scheduler(address, timeout_s=0.3)


def test_a_scheduler_like_answer_is_taken():
    listener, address = _server((300).to_bytes(8, "little") + b"x" * 300)
    with listener:
        assert check_scheduler(address, timeout_s=5) == address


def test_nothing_listening_is_refused():
    listener = socket.create_server(("127.0.0.1", 0))
    port = listener.getsockname()[1]
    listener.close()
    with pytest.raises(ConfigError, match="cannot reach the Dask scheduler"):
        check_scheduler(f"tcp://127.0.0.1:{port}", timeout_s=2)
