"""A ROS 2 bag opened within bounds: its metadata, its compressed files and chunks.

A bag of a few kilobytes can inflate to gigabytes: a rosbag2 folder whose files are zstd-
compressed (``compression_mode: file``), which ``rosbags`` would inflate unbounded into the
system's temporary folder; a message compressed on its own (``compression_mode: message``); an
MCAP chunk that declares (or hides) gigabytes. Here

* a file-compressed bag's files are inflated by scalf-opt itself into the bag's private copy
  (:func:`inflate_compressed_files`), within what is left of :data:`MAX_BAG_BYTES` for the
  whole bag, and its copied ``metadata.yaml`` then says the files are plain;
* every zstd frame ``rosbags`` inflates (an MCAP chunk, a compressed message) goes through
  :func:`bounded_zstd` while the bag is read (:func:`bounded_decompression`): at most
  :data:`MAX_CHUNK_BYTES`, and for an MCAP chunk no more than it declares;
* ``metadata.yaml`` is at most :data:`MAX_METADATA_BYTES` and lists each file once, at most
  :data:`MAX_BAG_FILES` files;
* a sqlite3 file holds what a recorder writes, tables and indexes with stored columns
  (:func:`check_sqlite_files`): a view (a recursive one never ends, in C code that no signal
  stops), a trigger, a virtual table or a generated column (a ``zeroblob`` of gigabytes in a
  file of kilobytes) is refused before ``rosbags`` queries the file.

A bag that breaks a bound is refused with one line naming the bag (not the private copy).
"""

from __future__ import annotations

import re
import sqlite3
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from scalf_opt.errors import LogError

MAX_BAG_BYTES = 512 * 1024 * 1024
"""Largest ROS 2 bag read (the files of a bag folder together, inflated) [bytes]: about 3.5
hours of a robot's 1 kHz joint states."""

MAX_CHUNK_BYTES = 64 * 1024 * 1024
"""Largest MCAP chunk or compressed message inflated [bytes] (a recorder's chunks: about 1 MB)."""

MAX_METADATA_BYTES = 1024 * 1024
"""Largest ``metadata.yaml`` of a bag folder [bytes] (a recorder's: a few kilobytes)."""

MAX_BAG_FILES = 1000
"""Most files a bag folder's metadata may list (a recorder splits a day into a few hundred)."""

MAX_VALUES = 100_000_000
"""Most numbers one topic may hold (800 MB as doubles): 12 motors' angle, rate and torque and 4
foot forces at 1 kHz for 42 minutes; a flood of messages is refused, not read into memory."""

MAX_JOINTS = 256
"""Most joints one message may name (far above any legged robot, far below what would cost
memory: a message of millions of names is refused before its names are compared)."""

_SQLITE_STEPS = 10_000_000
"""Most virtual-machine steps sqlite may take to answer the schema checks (a few thousand)."""

_FILE_MODE = re.compile(r"^(\s*compression_mode:\s*)['\"]?file['\"]?\s*$", re.MULTILINE | re.I)


def _zstd() -> Any:
    try:
        from compression import zstd
    except ImportError:
        from backports import zstd
    return zstd


def bounded_zstd(data: bytes, limit: int, shown: Path, what: str) -> bytes:
    """``data``'s zstd frames inflated, refused beyond ``limit`` bytes.

    Raises:
        LogError: More than ``limit`` bytes, or not zstd data (the message names ``shown``).
    """
    zstd = _zstd()
    out = bytearray()
    rest = bytes(data)
    try:
        while rest:
            decompressor = zstd.ZstdDecompressor()
            out += decompressor.decompress(rest, max_length=limit - len(out) + 1)
            if len(out) > limit:
                raise LogError(
                    f"{shown}: {what} inflates beyond {limit:,} bytes (a compression bomb, or "
                    "not a bag?)"
                )
            if not decompressor.eof:
                raise LogError(f"{shown}: {what} is a truncated zstd frame")
            rest = decompressor.unused_data
    except zstd.ZstdError as exc:
        raise LogError(f"{shown}: {what} is not valid zstd data ({exc})") from None
    return bytes(out)


def check_metadata(folder: Path, shown: Path) -> str:
    """The text of a copied bag folder's ``metadata.yaml``, checked (module docstring).

    Raises:
        LogError: Too large, not UTF-8, or listing a file twice or too many files.
    """
    metadata = folder / "metadata.yaml"
    if metadata.stat().st_size > MAX_METADATA_BYTES:
        raise LogError(
            f"{shown}/metadata.yaml: larger than the {MAX_METADATA_BYTES:,} bytes a bag's "
            "metadata may be"
        )
    try:
        text = metadata.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise LogError(f"{shown}/metadata.yaml: not UTF-8 text") from None
    names = re.findall(r"^\s*-\s*['\"]?([^'\"\n]+?)['\"]?\s*$", _file_list(text), re.MULTILINE)
    if len(names) > MAX_BAG_FILES:
        raise LogError(
            f"{shown}/metadata.yaml: lists {len(names)} files, more than {MAX_BAG_FILES}"
        )
    twice = sorted(name for name, count in Counter(names).items() if count > 1)
    if twice:
        raise LogError(f"{shown}/metadata.yaml: lists the file {twice[0][:100]!r} twice")
    return text


def _file_list(text: str) -> str:
    """The block of ``relative_file_paths:`` in a metadata text (its list items)."""
    match = re.search(r"relative_file_paths:\s*\n((?:[ \t]*-[^\n]*\n?)*)", text)
    return match.group(1) if match else ""


def inflate_compressed_files(folder: Path, shown: Path, budget: int) -> None:
    """Inflate a file-compressed bag's files in its private copy ``folder``, within ``budget``.

    Each ``*.zstd`` file becomes the file it holds (beside it, the compressed one removed), and
    the copied ``metadata.yaml`` says the bag is not compressed: ``rosbags`` then reads the
    plain files, and inflates nothing into the system's temporary folder.

    Raises:
        LogError: The bag inflates beyond ``budget`` bytes (:data:`MAX_BAG_BYTES` less its
            compressed size), or a file is not zstd data.
    """
    text = check_metadata(folder, shown)
    if not _FILE_MODE.search(text):
        return
    zstd = _zstd()
    left = budget
    for packed in sorted(folder.glob("*.zstd")):
        try:
            with zstd.open(packed, "rb") as source, packed.with_suffix("").open("wb") as target:
                while piece := source.read(1 << 20):
                    left -= len(piece)
                    if left < 0:
                        raise LogError(
                            f"{shown}: its compressed files inflate beyond the "
                            f"{MAX_BAG_BYTES:,} bytes a bag may hold (a compression bomb?)"
                        )
                    target.write(piece)
        except (zstd.ZstdError, EOFError) as exc:
            raise LogError(f"{shown}: {packed.name} is not valid zstd data ({exc})") from None
        packed.unlink()
    plain_text = _FILE_MODE.sub(lambda m: f"{m.group(1)}''", text)
    plain_text = re.sub(r"\.zstd(['\"]?)\s*$", r"\1", plain_text, flags=re.MULTILINE)
    (folder / "metadata.yaml").write_text(plain_text, encoding="utf-8")


def check_sqlite_files(local: Path, shown: Path) -> None:
    """Refuse a sqlite3 bag (``local``: its private copy) holding more than a recorder writes.

    ``shown``: the bag the user named. A file that is not a sqlite3 database is left to
    ``rosbags``, which says so.

    Raises:
        LogError: A ``.db3`` file holds a view, a trigger, a virtual table or a generated column
            (module docstring); the message names the file and the object.
    """
    files = sorted(local.glob("*.db3")) if local.is_dir() else [local]
    for database in files:
        where = shown / database.name if local.is_dir() else shown
        try:
            problem = _sqlite_problem(database)
        except sqlite3.DatabaseError:
            continue
        if problem:
            raise LogError(f"{where}: {problem}; a ROS 2 recorder writes tables of stored columns")


def _sqlite_problem(database: Path) -> str | None:
    """What in ``database`` a recorder does not write, or ``None``."""
    steps = iter(range(_SQLITE_STEPS // 100))
    connection = sqlite3.connect(f"{database.resolve().as_uri()}?mode=ro", uri=True)
    try:
        # called every 100 steps: a true answer interrupts the query
        connection.set_progress_handler(lambda: next(steps, None) is None, 100)
        objects = connection.execute("SELECT type, name, sql FROM sqlite_master").fetchall()
        for kind, name, sql in objects:
            shown = repr(str(name)[:100])
            if kind not in ("table", "index"):
                return f"the database holds a {kind} ({shown})"
            if kind == "table" and str(sql or "").lstrip().upper().startswith("CREATE VIRTUAL"):
                return f"the database holds a virtual table ({shown})"
        for kind, name, _ in objects:
            if kind != "table":
                continue
            columns = connection.execute("SELECT * FROM pragma_table_xinfo(?)", (name,))
            # the sixth field, "hidden": 2 and 3 mark a generated column
            generated = [column[1] for column in columns if column[6] in (2, 3)]
            if generated:
                return (
                    f"the table {str(name)[:100]!r} has a generated column "
                    f"({str(generated[0])[:100]!r})"
                )
    except sqlite3.OperationalError as exc:
        if "interrupted" in str(exc):
            return "its schema takes too long to read"
        raise sqlite3.DatabaseError(str(exc)) from None
    finally:
        connection.close()
    return None


@contextmanager
def bounded_decompression(shown: Path) -> Iterator[None]:
    """Inside: every zstd frame ``rosbags`` inflates is bounded (module docstring)."""
    import rosbags.rosbag2.reader as bag_reader
    import rosbags.rosbag2.storage_mcap as mcap

    table: dict[str, Callable[[bytes, int], bytes]] = mcap.DECOMPRESSORS
    saved_chunk = table["zstd"]
    saved_module = bag_reader.zstd

    class _Messages:
        """The ``zstd`` module as ``rosbags``' bag reader sees it: messages inflate bounded."""

        def __getattr__(self, name: str) -> Any:
            return getattr(saved_module, name)

        @staticmethod
        def decompress(data: bytes) -> bytes:
            return bounded_zstd(data, MAX_CHUNK_BYTES, shown, "a compressed message")

    table["zstd"] = lambda data, size: bounded_zstd(
        data, min(size, MAX_CHUNK_BYTES), shown, "an MCAP chunk"
    )
    bag_reader.zstd = _Messages()  # type: ignore[assignment]
    try:
        yield
    finally:
        table["zstd"] = saved_chunk
        bag_reader.zstd = saved_module
