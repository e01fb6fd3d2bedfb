"""A known synthetic Go1 trot written as Unitree's robots write it: a LowState bag, an SDK CSV.

``python examples/unitree_log.py PLAN_DIR OUT_DIR`` samples the plan saved in ``PLAN_DIR`` (the
``summary.json`` of ``scalf-opt evaluate --robot go1 --out PLAN_DIR``, or of ``optimize``) at
500 Hz over 6 cycles, starting 37 % into RF's cycle as a recording would, and writes
``OUT_DIR/go1_lowstate.mcap`` and ``OUT_DIR/go1_sdk.csv``: logs to try ``analyze-log`` on
before a robot's own (the tests read them too).

The trot is the plan of ``scalf-opt export`` (hip pitch and knee of every leg, their torques and
contacts) with an abduction motion added, ``q = A sin(w t + phi)``, ``tau = B cos(w t + phi)``,
so that the abduction does work the sagittal model does not: ``integral |tau dq|`` over a cycle
is exactly ``pi A B`` (0.754 J per hip), a closed form the tests check the reader against. The
bag is written with ``rosbags``' writer and the message definitions of ``unitree_ros2``'s
``unitree_go`` package embedded, as a recorder does: nothing of scalf-opt's own writer.
"""

# ruff: noqa: I001  (scalf_opt first: numpy then runs on the BLAS kernels it pins)
from __future__ import annotations

import scalf_opt  # noqa: F401
import csv
from pathlib import Path

import numpy as np

UNITREE_GO_MSGS = {
    "unitree_go/msg/MotorState": """uint8 mode
float32 q
float32 dq
float32 ddq
float32 tau_est
float32 q_raw
float32 dq_raw
float32 ddq_raw
int8 temperature
uint32 lost
uint32[2] reserve
""",
    "unitree_go/msg/IMUState": """float32[4] quaternion
float32[3] gyroscope
float32[3] accelerometer
float32[3] rpy
int8 temperature
""",
    "unitree_go/msg/BmsState": """uint8 version_high
uint8 version_low
uint8 status
uint8 soc
int32 current
uint16 cycle
int8[2] bq_ntc
int8[2] mcu_ntc
uint16[15] cell_vol
""",
    "unitree_go/msg/LowState": """uint8[2] head
uint8 level_flag
uint8 frame_reserve
uint32[2] sn
uint32[2] version
uint16 bandwidth
IMUState imu_state
MotorState[20] motor_state
BmsState bms_state
int16[4] foot_force
int16[4] foot_force_est
uint32 tick
uint8[40] wireless_remote
uint8 bit_flag
float32 adc_reel
int8 temperature_ntc1
int8 temperature_ntc2
float32 power_v
float32 power_a
uint16[4] fan_frequency
uint32 reserve
uint32 crc
""",
}

LEG_PREFIX = {"RF": "FR", "LF": "FL", "RH": "RR", "LH": "RL"}
UNITREE_ORDER = [
    f"{p}_{part}_joint" for p in ("FR", "FL", "RR", "RL") for part in ("hip", "thigh", "calf")
]
ABDUCTION_RAD = 0.06
ABDUCTION_NM = 4.0
STANCE_FORCE = 120  # a foot sensor's reading in stance (int16 counts), 0 in swing


def synthetic_trot(export, cycles_skip: float = 0.0):
    """Every Unitree motor's (q, dq, tau) and the foot forces of an export, shape (12, n), (4, n).

    ``cycles_skip`` drops that share of a cycle at the start: a recording at another phase.
    """
    t = export.t_s
    period = export.saved.gait.period_s
    w = 2.0 * np.pi / period
    q = np.zeros((12, t.size))
    dq = np.zeros_like(q)
    tau = np.zeros_like(q)
    force = np.zeros((4, t.size))
    for leg, prefix in LEG_PREFIX.items():
        v = export.values[leg]
        base = UNITREE_ORDER.index(f"{prefix}_hip_joint")
        phase = {"RF": 0.0, "LH": 0.0, "LF": np.pi, "RH": np.pi}[leg]
        q[base] = ABDUCTION_RAD * np.sin(w * t + phase)
        dq[base] = ABDUCTION_RAD * w * np.cos(w * t + phase)
        tau[base] = ABDUCTION_NM * np.cos(w * t + phase)
        q[base + 1 : base + 3] = v["q"]
        dq[base + 1 : base + 3] = v["qd"]
        tau[base + 1 : base + 3] = v["tau"]
        force[("FR", "FL", "RR", "RL").index(prefix)] = STANCE_FORCE * v["contact"]
    start = round(cycles_skip * period / (t[1] - t[0]))
    return t[start:] - t[start], q[:, start:], dq[:, start:], tau[:, start:], force[:, start:]


def write_lowstate_bag(
    path: Path,
    t,
    q,
    dq,
    tau,
    force,
    topic="/lowstate",
    t0_s=1_767_225_600.0,
    odometry_speed_m_s=None,
):
    """A ``unitree_go/msg/LowState`` MCAP bag with its definitions embedded (module docstring).

    With ``odometry_speed_m_s``, a ``nav_msgs/msg/Odometry`` topic ``/odom`` at a tenth of the
    rate: the trunk moving forward at that speed.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    for name, text in UNITREE_GO_MSGS.items():
        store.register(get_types_from_msg(text, name))
    types = store.types
    motor, imu, bms = (
        types["unitree_go/msg/MotorState"],
        types["unitree_go/msg/IMUState"],
        types["unitree_go/msg/BmsState"],
    )
    low = types["unitree_go/msg/LowState"]
    u8, u16, u32 = np.uint8, np.uint16, np.uint32
    i8, i16, f32 = np.int8, np.int16, np.float32
    folder = path.parent / (path.stem + "-bag")
    with Writer(folder, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = writer.add_connection(topic, "unitree_go/msg/LowState", typestore=store)
        for k, tk in enumerate(t):
            motors = [
                motor(
                    10,
                    float(q[j, k]) if j < 12 else 0.0,
                    float(dq[j, k]) if j < 12 else 0.0,
                    0.0,
                    float(tau[j, k]) if j < 12 else 0.0,
                    0.0,
                    0.0,
                    0.0,
                    30,
                    0,
                    np.zeros(2, u32),
                )
                for j in range(20)
            ]
            msg = low(
                np.zeros(2, u8),
                255,
                0,
                np.zeros(2, u32),
                np.zeros(2, u32),
                0,
                imu(
                    np.array([1, 0, 0, 0], f32),
                    np.zeros(3, f32),
                    np.zeros(3, f32),
                    np.zeros(3, f32),
                    30,
                ),
                motors,
                bms(0, 0, 0, 90, 0, 0, np.zeros(2, i8), np.zeros(2, i8), np.zeros(15, u16)),
                force[:, k].astype(i16),
                np.zeros(4, i16),
                k,
                np.zeros(40, u8),
                0,
                0.0,
                30,
                30,
                25.0,
                1.0,
                np.zeros(4, u16),
                0,
                0,
            )
            data = store.serialize_cdr(msg, "unitree_go/msg/LowState")
            writer.write(conn, round((t0_s + float(tk)) * 1e9), data)
        if odometry_speed_m_s is not None:
            _write_odometry(writer, store, t, t0_s, odometry_speed_m_s)
    (folder / f"{folder.name}.mcap").rename(path)
    for leftover in folder.iterdir():
        leftover.unlink()
    folder.rmdir()
    return path


def _write_odometry(writer, store, t, t0_s, speed_m_s):
    types = store.types
    odom = "nav_msgs/msg/Odometry"
    conn = writer.add_connection("/odom", odom, typestore=store)
    header, stamp = types["std_msgs/msg/Header"], types["builtin_interfaces/msg/Time"]
    pose_cov, pose = types["geometry_msgs/msg/PoseWithCovariance"], types["geometry_msgs/msg/Pose"]
    point, quat = types["geometry_msgs/msg/Point"], types["geometry_msgs/msg/Quaternion"]
    twist_cov, twist = (
        types["geometry_msgs/msg/TwistWithCovariance"],
        types["geometry_msgs/msg/Twist"],
    )
    vector = types["geometry_msgs/msg/Vector3"]
    for tk in t[::10]:
        ns = round((t0_s + float(tk)) * 1e9)
        msg = types[odom](
            header(stamp(ns // 1_000_000_000, ns % 1_000_000_000), "odom"),
            "base",
            pose_cov(
                pose(point(speed_m_s * float(tk), 0.0, 0.3), quat(0.0, 0.0, 0.0, 1.0)), np.zeros(36)
            ),
            twist_cov(twist(vector(speed_m_s, 0.0, 0.0), vector(0.0, 0.0, 0.0)), np.zeros(36)),
        )
        writer.write(conn, ns, store.serialize_cdr(msg, odom))


def write_sdk_csv(path: Path, t, q, dq, tau, force):
    """An SDK-style wide CSV: ``time_ms``, ``q_i``, ``dq_i``, ``tau_est_i``, ``foot_force_i``."""
    header = ["time_ms"]
    header += [f"q_{i}" for i in range(12)] + [f"dq_{i}" for i in range(12)]
    header += [f"tau_est_{i}" for i in range(12)] + [f"foot_force_{i}" for i in range(4)]
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for k, tk in enumerate(t):
            row = [f"{tk * 1e3:.3f}"]
            for array in (q, dq, tau):
                row += [f"{v:.6g}" for v in array[:, k]]
            row += [str(int(v)) for v in force[:, k]]
            writer.writerow(row)
    return path


def exact_energy_j(t, dq, tau, period_s):
    """Every motor's mean ``integral |tau dq|`` per cycle over the whole cycles [J], dense."""
    power = np.abs(tau * dq)
    cycles = int(np.floor((t[-1] - t[0]) / period_s + 1e-9))
    end = np.searchsorted(t, t[0] + cycles * period_s + 1e-9)
    return np.trapezoid(power[:, :end], t[:end], axis=1) / cycles


def main(argv: list[str] | None = None) -> None:
    """Write the two logs of a saved plan (module docstring)."""
    import sys

    from scalf_opt.api import export_plan

    plan, out = (argv if argv is not None else sys.argv[1:])[:2]
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    export = export_plan(plan, "go1", rate_hz=500, cycles=6).export
    arrays = synthetic_trot(export, cycles_skip=0.37)
    for path in (
        write_lowstate_bag(folder / "go1_lowstate.mcap", *arrays),
        write_sdk_csv(folder / "go1_sdk.csv", *arrays),
    ):
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
