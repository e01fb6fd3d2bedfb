"""Compressed bags read within bounds: file-, message- and chunk-compressed bags are read as
plain ones are, and a bag that inflates beyond its bound is refused with one line, leaving
nothing in the system's temporary folder."""

import numpy as np
import pytest

import scalf_opt.io.bag_bounds as bounds
import scalf_opt.io.ros_bag as ros_bag
from scalf_opt.errors import LogError
from scalf_opt.io.ros_bag import read_joint_states

NAMES = ("a", "b")


def write(folder, mode=None, storage="sqlite3", messages=400):
    """A JointState bag of ``messages`` messages, compressed by ``mode`` (file, message,
    storage: MCAP chunks), as ``rosbags``' writer (a recorder's library) writes it."""
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    state = store.types["sensor_msgs/msg/JointState"]
    header, stamp = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    writer = Writer(folder, version=9, storage_plugin=plugin)
    if mode is not None:
        writer.set_compression(getattr(CompressionMode, mode.upper()), CompressionFormat.ZSTD)
    with writer:
        conn = writer.add_connection("/joint_states", state.__msgtype__, typestore=store)
        for k in range(messages):
            t = 1.0 + 0.001 * k
            values = np.array([np.sin(t), np.cos(t)])
            msg = state(header(stamp(1, k * 1_000_000), "b"), list(NAMES), values, values, values)
            writer.write(conn, round(t * 1e9), store.serialize_cdr(msg, state.__msgtype__))
    return folder


@pytest.mark.parametrize(
    ("mode", "storage"),
    [
        (None, "sqlite3"),
        ("file", "sqlite3"),
        ("message", "sqlite3"),
        ("storage", "mcap"),
        ("file", "mcap"),
    ],
)
def test_compressed_bags_read_as_plain_ones(tmp_path, mode, storage, monkeypatch):
    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", None)
    plain = read_joint_states(write(tmp_path / "plain", storage=storage))
    packed = read_joint_states(write(tmp_path / "packed", mode, storage))
    np.testing.assert_array_equal(packed.position, plain.position)
    np.testing.assert_array_equal(packed.t_s, plain.t_s)
    assert list((tmp_path / "tmp").iterdir()) == []  # nothing inflated outside the scratch


def test_a_file_compressed_bag_that_inflates_too_far_is_refused(tmp_path, monkeypatch):
    bag = write(tmp_path / "bomb", "file", messages=2000)
    packed = sum(f.stat().st_size for f in bag.iterdir())
    # the compressed bag fits, the files it holds do not
    monkeypatch.setattr(ros_bag, "MAX_BAG_BYTES", 2 * packed)
    with pytest.raises(LogError, match=r"bomb: its compressed files inflate beyond"):
        read_joint_states(bag)


@pytest.mark.parametrize(
    ("mode", "storage", "what"),
    [("storage", "mcap", "an MCAP chunk"), ("message", "sqlite3", "a compressed message")],
)
def test_a_chunk_or_message_that_inflates_too_far_is_refused(
    tmp_path, monkeypatch, mode, storage, what
):
    bag = write(tmp_path / "bomb", mode, storage)
    monkeypatch.setattr(bounds, "MAX_CHUNK_BYTES", 100)  # a message is ~130 bytes, a chunk more
    with pytest.raises(LogError, match=f"bomb: {what} inflates beyond 100 bytes"):
        read_joint_states(bag)
    import rosbags.rosbag2.reader as reader
    import rosbags.rosbag2.storage_mcap as mcap

    # restored once the bag is closed
    assert reader.zstd.__name__.endswith("zstd")
    assert mcap.DECOMPRESSORS["zstd"].__module__ == "rosbags.rosbag2.storage_mcap"


def test_metadata_that_lists_a_file_twice_or_is_huge_is_refused(tmp_path, monkeypatch):
    bag = write(tmp_path / "twice")
    metadata = bag / "metadata.yaml"
    text = metadata.read_text()
    listed = text.split("relative_file_paths:\n")[1].splitlines()[0]
    metadata.write_text(text.replace(listed, listed + "\n" + listed, 1))
    with pytest.raises(LogError, match=r"twice/metadata\.yaml: lists the file .* twice"):
        read_joint_states(bag)
    metadata.write_text(text + "#" * (bounds.MAX_METADATA_BYTES + 1))
    with pytest.raises(LogError, match=r"metadata\.yaml: larger than the 1,048,576 bytes"):
        read_joint_states(bag)


def test_a_bag_folder_too_large_in_all_is_named_with_its_total(tmp_path, monkeypatch):
    bag = write(tmp_path / "big", messages=50)
    total = sum(f.stat().st_size for f in bag.iterdir())
    monkeypatch.setattr(ros_bag, "MAX_BAG_BYTES", total - 1)
    with pytest.raises(LogError, match=rf"big: its files hold {total:,} bytes together, more than"):
        read_joint_states(bag)


def test_a_full_temporary_folder_is_not_blamed_on_the_bag(tmp_path, monkeypatch):
    import errno
    import io

    import scalf_opt.files as files

    class Full(io.BytesIO):
        def write(self, data):
            raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files, "open", lambda path, mode: Full(), raising=False)
    bag = write(tmp_path / "bag", storage="mcap", messages=20)
    mcap = next(bag.glob("*.mcap"))
    with pytest.raises(
        LogError,
        match=r"cannot copy the bag into the temporary folder .* \(No "
        r"space left on device\): free space there, or set TMPDIR",
    ):
        read_joint_states(mcap)


@pytest.mark.parametrize("damage", ["metadata", "file"])
def test_errors_name_the_users_bag_not_the_private_copy(tmp_path, damage):
    bag = write(tmp_path / "mine", messages=20)
    if damage == "metadata":
        (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: [unclosed\n")
    else:
        database = next(bag.glob("*.db3"))
        database.write_bytes(database.read_bytes()[:100])
    with pytest.raises(LogError) as info:
        read_joint_states(bag)
    message = str(info.value)
    assert message.startswith(f"{bag}: ") and "scalf-opt-bag-" not in message, message


def test_a_message_of_too_many_joints_or_a_flood_is_refused(tmp_path, monkeypatch):
    """Checked before the names are compared (a quadratic check took minutes on 5 M names)."""
    from scalf_opt.io.ros_bag import JointStateSeries, write_bag

    many = tuple(f"j{k}" for k in range(300))
    values = np.zeros((300, 3))
    bag = write_bag(tmp_path / "wide.mcap", [JointStateSeries("/js", many, np.arange(3.0), values)])
    with pytest.raises(LogError, match=r"message 0: 300 joints, more than the 256 a message"):
        read_joint_states(bag)
    monkeypatch.setattr(ros_bag, "MAX_VALUES", 1000)
    bag = write(tmp_path / "flood", messages=400)  # 400 messages x 3 x 2 joints = 2,400 numbers
    with pytest.raises(LogError, match=r"holds more than 1,000 numbers"):
        read_joint_states(bag)


# What a recorder never writes into its sqlite3 file, each as a hostile bag would hold it: a
# recursive view spun forever in sqlite's C code (no signal stopped it), a generated column
# conjured a gigabyte from a file of kilobytes.
_SCHEMA_ATTACKS = {
    "recursive view": (
        "ALTER TABLE schema RENAME TO s0; CREATE VIEW schema AS WITH RECURSIVE r(v, d) AS "
        "(SELECT schema_version, ros_distro FROM s0 UNION ALL SELECT v, d FROM r) "
        "SELECT * FROM r ORDER BY 1",
        r"bag/bag\.db3: the database holds a view \('schema'\)",
    ),
    "generated column": (
        "ALTER TABLE messages RENAME TO m0; CREATE TABLE messages(id INTEGER PRIMARY KEY, "
        "topic_id INTEGER, timestamp INTEGER, kept BLOB, data BLOB GENERATED ALWAYS AS "
        "(zeroblob(1000000000)) VIRTUAL); INSERT INTO messages(id, topic_id, timestamp, kept) "
        "SELECT id, topic_id, timestamp, data FROM m0; DROP TABLE m0",
        r"the table 'messages' has a generated column \('data'\)",
    ),
    "trigger": (
        "CREATE TRIGGER t AFTER INSERT ON topics BEGIN DELETE FROM messages; END",
        r"the database holds a trigger \('t'\)",
    ),
}


@pytest.mark.parametrize("attack", sorted(_SCHEMA_ATTACKS))
def test_a_sqlite_bag_holding_more_than_tables_is_refused(tmp_path, attack):
    import sqlite3

    script, message = _SCHEMA_ATTACKS[attack]
    bag = write(tmp_path / "bag", messages=20)
    database = sqlite3.connect(bag / "bag.db3")
    database.executescript(script)
    database.close()
    with pytest.raises(LogError, match=message):
        read_joint_states(bag)


def test_a_sqlite_bag_s_schema_checks_are_bounded(tmp_path, monkeypatch):
    bag = write(tmp_path / "bag", messages=20)
    monkeypatch.setattr(bounds, "_SQLITE_STEPS", 0)  # none: the first hundred steps stop it
    with pytest.raises(LogError, match=r"bag/bag\.db3: its schema takes too long to read"):
        read_joint_states(bag)
