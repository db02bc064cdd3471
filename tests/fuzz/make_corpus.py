"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/).

The seeds are committed; this script documents how they were made and
remakes them after a change of a wire format:

    .venv/bin/python tests/fuzz/make_corpus.py [BUILD_DIR]

BUILD_DIR (default build/host) holds the generated LCM Python bindings. Each
seed is a realistic input in the target's layout (see the target's source):
valid frames and configurations, plus the forged ones of issue 11, so the
fuzzer starts from inputs that reach deep into the code.
"""
from __future__ import annotations

import hashlib
import struct
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "sil"))

from aocs_pil import frame  # noqa: E402  (the project's own PIL codec, the C one's mirror)

Q = (0.0, 0.0, 0.0871557427476582, 0.9961946980917455)
W = (0.01, -0.02, 0.03)


def _bindings(build: Path):
    sys.path.insert(0, str(build / "lcmtypes" / "python"))
    import aocs_lcm  # deferred: generated at build time, path known only here

    return aocs_lcm


def _write(target: str, name: str, data: bytes) -> None:
    d = HERE / "corpus" / target
    d.mkdir(parents=True, exist_ok=True)
    (d / f"{name}-{hashlib.sha1(data).hexdigest()[:8]}").write_bytes(data)


def _chunks(payloads) -> bytes:
    return b"".join(struct.pack("<H", len(p)) + p for p in payloads)


def sensors_seeds(t) -> None:
    s = t.sensors_t

    def msg(frame_no, tick, t_s, valid=s.VALID_ATTITUDE | s.VALID_RATE, version=None, q=Q, w=W):
        m = s()
        m.protocol_version = s.PROTOCOL_VERSION if version is None else version
        m.frame, m.utime, m.tick, m.t_s, m.valid = frame_no, tick * 100000, tick, t_s, valid
        m.q, m.w, m.pos, m.vel = list(q), list(w), [1.0, -1.0, -6.0], [0.05, -0.1, 0.35]
        return m.encode()

    good = [msg(k, k, 0.1 * k) for k in range(8)]

    def wheels(frame_no, tick, n=4, speeds=(100.0, -250.0, 599.0, 0.5)):
        m = s()
        m.protocol_version = s.PROTOCOL_VERSION
        m.frame, m.utime, m.tick, m.t_s = frame_no, tick * 100000, tick, 0.1 * tick
        m.valid = s.VALID_ATTITUDE | s.VALID_RATE | s.VALID_WHEELS
        m.q, m.w, m.n_wheels = list(Q), list(W), n
        m.wheel_speed = list(speeds) + [0.0] * (6 - len(speeds))
        return m.encode()

    def star_gyro(frame_no, tick, t_meas, valid=s.VALID_ATTITUDE | s.VALID_RATE | s.VALID_GYRO, st_q=Q):
        m = s()
        m.protocol_version = s.PROTOCOL_VERSION
        m.frame, m.utime, m.tick, m.t_s, m.valid = frame_no, tick * 100000, tick, 0.1 * tick, valid
        m.q, m.w, m.st_q, m.st_t_meas_s, m.gyro_w = list(Q), list(W), list(st_q), t_meas, [0.011, -0.021, 0.029]
        return m.encode()

    st_new = s.VALID_ATTITUDE | s.VALID_RATE | s.VALID_GYRO | s.VALID_STAR_TRACKER
    st_frames = [star_gyro(k, k, 0.1 * k - 0.1 if k else 0.0, st_new if k % 2 == 0 else st_new & ~s.VALID_STAR_TRACKER)
                 for k in range(8)]
    # protocol version 3: the tracker's samples with their time of measurement, the gyro; then absurd times
    _write("fuzz_sensors", "star_tracker_gyro", bytes([4]) + _chunks(st_frames))
    _write("fuzz_sensors", "star_tracker_realtime", bytes([5]) + _chunks(st_frames))

    def mag(frame_no, tick, b, valid=s.VALID_ATTITUDE | s.VALID_RATE | s.VALID_MAGNETOMETER):
        m = s()
        m.protocol_version = s.PROTOCOL_VERSION
        m.frame, m.utime, m.tick, m.t_s, m.valid = frame_no, tick * 100000, tick, 0.1 * tick, valid
        m.q, m.w, m.mag_b_t = list(Q), list(W), list(b)
        return m.encode()

    # protocol version 4: the magnetometer, with and without its flag, then NaN and huge fields
    _write("fuzz_sensors", "magnetometer", bytes([4]) + _chunks(
        [mag(k, k, (2e-5, -1e-5 * k, 3e-6), s.VALID_ATTITUDE | s.VALID_RATE | (s.VALID_MAGNETOMETER if k % 2 else 0))
         for k in range(6)] + [mag(6, 6, (float("nan"), 0.0, 0.0)), mag(7, 7, (1e300, -1e300, 0.0))]))
    _write("fuzz_sensors", "star_tracker_bad_times", bytes([4]) + _chunks(
        st_frames[:3] + [star_gyro(3 + i, 3 + i, t, st_new) for i, t in enumerate(
            (float("nan"), -1.0, 1e300, 1.8e10, 1e9, float("inf")))]
        + [star_gyro(9, 9, 0.8, st_new, st_q=(0.0, 0.0, 0.0, 2.0)),
           star_gyro(10, 10, 0.9, st_new, st_q=(float("nan"),) * 4)]))
    _write("fuzz_sensors", "wheels", bytes([4]) + _chunks([wheels(k, k) for k in range(6)] + [wheels(6, 6, n=9),
                                                           wheels(7, 7, speeds=(float("nan"), 0.0, 0.0, 0.0))]))
    _write("fuzz_sensors", "lockstep_good", bytes([4]) + _chunks(good))
    _write("fuzz_sensors", "realtime_good", bytes([5]) + _chunks(good))
    _write("fuzz_sensors", "future_time", bytes([4]) + _chunks(good[:4] + [msg(4, 4, 1e9)] + good[5:]))
    _write("fuzz_sensors", "int64_max", bytes([4]) + _chunks(good[:4] + [msg(2**63 - 1, 4, 0.4)] + good[4:]))
    _write("fuzz_sensors", "int64_min_max", bytes([4]) + _chunks([msg(-(2**63), 0, 0.0), msg(2**63 - 1, 1, 0.1)]
                                                                  + good))
    _write("fuzz_sensors", "tick_far", bytes([4]) + _chunks(good[:3] + [msg(3, 3 + 2**30, 1e8)] + good[4:]))
    _write("fuzz_sensors", "orbit", bytes([20]) + _chunks([msg(k, k, 0.1 * k, valid=12) for k in range(5)]))
    _write("fuzz_sensors", "malformed", bytes([4]) + _chunks([b"", good[0][:-3], good[1] + b"\0",
                                                              msg(2, 2, 0.2, version=7), good[3]]))
    _write("fuzz_sensors", "big_times", bytes([4]) + _chunks([msg(k, k, t) for k, t in
                                                              enumerate((9.3e9, 1e10, 1.79e10, 1e300, -1.0))]))


def command_seeds(t) -> None:
    c = t.command_t

    def cmd(request, law_id=c.LAW_KEEP, mode=c.MODE_KEEP, qd=None, wd=(0.0, 0.0, 0.0)):
        m = c()
        m.protocol_version, m.frame, m.utime, m.request = c.PROTOCOL_VERSION, request, 0, request
        m.law_id, m.mode, m.set_target = law_id, mode, qd is not None
        m.qd, m.wd = list(qd if qd is not None else (0.0, 0.0, 0.0, 1.0)), list(wd)
        return m.encode()

    _write("fuzz_commands", "laws", bytes([2]) + _chunks([cmd(i, law_id=i) for i in range(-1, 12)]))
    _write("fuzz_commands", "modes", bytes([2]) + _chunks([cmd(i, mode=m) for i, m in enumerate((-1, 0, 1, 2, 3))]))
    _write("fuzz_commands", "targets", bytes([1]) + _chunks([cmd(1, qd=(0.1, -0.2, 0.3, 0.9273618495495703)),
                                                             cmd(2, qd=(0, 0, 0, 2)), cmd(3, qd=Q, wd=(1e-3, 0, 0))]))
    _write("fuzz_commands", "standby_nominal", bytes([6]) + _chunks([cmd(1, mode=0), cmd(2, mode=1),
                                                                     cmd(3, law_id=10, mode=1)]))


CONFIGS = {
    "base": "law = quat_pd\nmode = lockstep\ncontrol_period_s = 0.1\nquat_pd.kp = 4\nquat_pd.kd = 8\n"
            "u_max_axis = 0.5 0.6 0.7\nk_safe = 2\nrecover_good_samples = 3\nidle_timeout_s = 5\n",
    "realtime": "law = crp_linear\nmode = realtime\ncontrol_period_s = 0.02\ncrp_linear.k1 = 19\n"
                "crp_linear.k2 = 13\nu_max_norm = 0.2\nstale_timeout_s = 0.05\nrun_timeout_s = 10\n",
    "tables": "law = hinf\nhinf.table = hinf_regional\nlqr_quat.table = lqr_quat_ref\n"
              "orbit_lqr.table = orbit_lqr_q1\nu_max_axis = 1 1 1\nu_max_norm = 1.5\n",
    "smc": "law = smc\nu_max_axis = 1, 1, 1\ninertia = 10 12 15\nsmc.lambda = 1 1 1\nsmc.g = 0.05 0.05 0.05\n"
           "smc.eps = 0.02 0.02 0.02\n# comment\n\ntarget_q = 0 0 0.2588190451 0.9659258263\n",
    "mrp": "law = mrp_sat_tanh\nu_max_axis = 1 1 1\nmrp_sat.k = 50\nmrp_sat.lambda = 0.6\nmrp_sat.u_max = 0.05\n"
           "mrp_sat.l1 = 0.05 0.05 0.05\nmrp_sat.m1 = 0.05 0.05 0.05\nmrp_sat.l2 = 0.0577 0.0577 0.0577\n"
           "mrp_sat.m2 = 0.0577 0.0577 0.0577\n",
    "rotating": "law = quat_pd\nquat_pd.kp = 4\nquat_pd.kd = 8\nu_max_axis = 0.2 0.2 0.2\n"
                "target_rotation_rate = 0 -7.292115e-5 0\n",
    "orbit": "law = orbit_lqr\norbit_lqr.k = " + " ".join(["0.1"] * 18) + "\nu_max_norm = 2\nbudget_ns = 5000\n",
    "issue11_limits": "law = quat_pd\nquat_pd.kp = 4\nquat_pd.kd = 8\nu_max_axis = 1e150 1e-170 1e150\n"
                      "u_max_norm = 1e150\n",
    "issue11_timeouts": "law = none\nu_max_norm = 1\nidle_timeout_s = 2e10\nstatus_period_s = 1e-10\n",
    "errors": "law = quat_pd\nbogus = 1\n",
    # the SPEC 5.3 pyramid about x, wheel 0 failed (docs/wire-contract.md "Reaction wheels")
    "wheels": "law = quat_pd\nquat_pd.kp = 4\nquat_pd.kd = 8\nu_max_axis = 1 1 1\ninertia = 2059.5 5954.2 5974.3\n"
              "wheels.count = 4\nwheels.failed_mask = 1\n" + "".join(
                  f"wheel{i}.axis_B = {a}\nwheel{i}.js_kgm2 = 0.08\nwheel{i}.u_max_nm = 0.25\nwheel{i}.omega_max_radps = 600\n"
                  for i, a in enumerate(("0.57735 0.81650 0", "0.57735 0 0.81650", "0.57735 -0.81650 0",
                                         "0.57735 0 -0.81650"))),
    # the same with the friction feedforward model and the null-space management (docs/spec.md 5.3.2)
    "wheels_friction": "law = quat_pd\nquat_pd.kp = 4\nquat_pd.kd = 8\nu_max_axis = 1 1 1\n"
                       "inertia = 2059.5 5954.2 5974.3\nwheels.count = 4\nwheels.null_gain = 0.02\n" + "".join(
                           f"wheel{i}.axis_B = {a}\nwheel{i}.js_kgm2 = 0.08\nwheel{i}.u_max_nm = 0.25\nwheel{i}.omega_max_radps = 600\n"
                           f"wheel{i}.viscous_nms = 1e-5\nwheel{i}.coulomb_nm = 2e-3\nwheel{i}.coulomb_width_radps = 0.5\n"
                           f"wheel{i}.null_speed_radps = {50 if i % 2 == 0 else -50}\n"
                           for i, a in enumerate(("0.57735 0.81650 0", "0.57735 0 0.81650", "0.57735 -0.81650 0",
                                                  "0.57735 0 -0.81650"))),
}


def config_seeds() -> None:
    for name, text in CONFIGS.items():
        _write("fuzz_node_config", name, text.encode())


def exec_seeds() -> None:
    def step(tick_mode=0, time_mode=0, valid=0x83, extra=b""):
        # op 0 (step), tick mode, time mode, [raw fields], valid flags | 0x80 (unit q from 3 bytes)
        return bytes([0, tick_mode, time_mode]) + extra + bytes([valid, 10, 20, 30]) + struct.pack(
            "<9d", *W, 1.0, 0.01, -1.0, 0.0, 5.0, -0.01)

    header = bytes([2, 0, 0]) + struct.pack("<4H", 30000, 30000, 30000, 30000) + bytes([3, 3]) + struct.pack(
        "<H", 32)
    body = b"".join(step() for _ in range(6))
    _write("fuzz_exec_step", "lockstep_quat_pd", header + body)
    _write("fuzz_exec_step", "future_time", header + step() + step(time_mode=255, extra=struct.pack("<Q", 10**27 % 2**64))
           + b"".join(step() for _ in range(6)))
    _write("fuzz_exec_step", "tick_far", header + step() + step(tick_mode=255, extra=struct.pack("<I", 2**30))
           + b"".join(step() for _ in range(6)))
    rt = bytes([7, 1 | (2 << 1), 5]) + struct.pack("<4H", 20000, 40000, 60000, 30000) + bytes([2, 2]) + struct.pack(
        "<H", 10)
    _write("fuzz_exec_step", "realtime_both_limits", rt + b"".join(step(valid=0x83) for _ in range(6))
           + bytes([6, 6, 6]) + b"".join(step() for _ in range(4)))
    sel = bytes([7, 5, 3]) + struct.pack("<4d", 0, 0, 0, 1) + bytes([3, 20, 20, 20])
    _write("fuzz_exec_step", "select", header + step() + sel + step() + bytes([7, 0, 0]) + struct.pack("<4d", 0, 0, 0, 1)
           + step())
    orbit = bytes([10, 2 << 1, 0]) + struct.pack("<4H", 30000, 30000, 30000, 40000) + bytes([3, 3]) + struct.pack(
        "<H", 32)
    _write("fuzz_exec_step", "orbit", orbit + b"".join(step(valid=0x84) for _ in range(5)))
    # quat_pd on the reaction wheel pyramid (flags bit5), wheel 3 failed in the second seed (bit6): each step
    # then carries 4 tachometer readings as u16 (+-1000 rad/s), 0x8000 = 0 rad/s, 0x8010 = 0.49 rad/s
    tach = struct.pack("<4H", 0x8000, 0x8010, 0x7FF0, 0xC000)
    wheels = bytes([2, 32, 0]) + struct.pack("<4H", 30000, 30000, 30000, 30000) + bytes([3, 3]) + struct.pack(
        "<H", 32)
    _write("fuzz_exec_step", "wheels", wheels + b"".join(step(extra=b"") + tach for _ in range(6)))
    wheels_failed = bytes([11, 32 | 64, 0]) + wheels[3:]
    # the MEKF as the estimator (flags bit7): gyro (bit4) every step, the tracker (bit3) every 5th
    mekf = bytes([2, 128, 0]) + header[3:]
    _write("fuzz_exec_step", "mekf", mekf + b"".join(step(valid=0x98 if k % 5 == 0 else 0x90) for k in range(12)))
    _write("fuzz_exec_step", "wheels_failed", wheels_failed + b"".join(step() + tach for _ in range(6))
           + bytes([6, 6]) + step() + tach)


def mekf_seeds() -> None:
    # fuzz_mekf_step: config mode, then steps (op 0, verdict, time mode, valid, 3 x u16 gyro, 3 x u8 q, u8 age)
    def step(valid=0x18, verdict=0, time_mode=0, age=0, q=(128, 130, 126)):
        return bytes([0, verdict, time_mode, valid]) + struct.pack("<3H", 32768 + 82, 32768 - 164, 32768 + 41) + \
            bytes(q) + bytes([age])

    good = step() + b"".join(step(valid=0x10 if k % 5 else 0x18) for k in range(1, 40))
    _write("fuzz_mekf_step", "tracker_every_5", bytes([0]) + good)
    _write("fuzz_mekf_step", "waiting", bytes([0]) + b"".join(step(valid=0x10) for _ in range(8)) + step())
    _write("fuzz_mekf_step", "delayed", bytes([0]) + step() + b"".join(
        step(valid=0x10 if k % 5 else 0x18, age=0 if k < 35 else 200) for k in range(1, 60)))
    _write("fuzz_mekf_step", "hostile", bytes([0]) + good + step(valid=0x18, age=255) + step(valid=0x58)
           + struct.pack("<4d", float("nan"), 0.0, 0.0, 1.0) + step(valid=0x18, q=(250, 3, 3)) + step(verdict=5)
           + bytes([7]) + step())
    _write("fuzz_mekf_step", "tuned", bytes([3]) + struct.pack("<8H", *(32768,) * 8) + bytes([10, 0, 0]) + good)
    # the gyro excluded after 40 steps (op 8: a diagonal inertia of 10^(160 / 64) ~ 316 kg m^2), a torque held
    # (op 9), then steps with the tracker's flag only (0x08: no gyro), a reset and one more
    gyroless = bytes([8, 0, 160, 170, 180, 10, 10, 10]) + bytes([9, 0]) + struct.pack("<6H", 33000, 32000, 32768,
                                                                                         40000, 30000, 32768)
    _write("fuzz_mekf_step", "gyroless", bytes([8, 1]) + struct.pack("<3H", 40000, 50000, 30000) + good + gyroless
           + b"".join(step(valid=0x08) for _ in range(30)) + bytes([7]) + step(valid=0x08))


def momentum_seeds() -> None:
    # fuzz_momentum_step: u8 policy, u8 trigger, u8 raw, the parameters as u16 (3 x (target, limit, 3 axis
    # perturbations), h_start, h_stop, k, dump torque, u8 count, thrust, min on, quantum, 12 x 3 arms), then
    # steps: u8 flags, h[3], b[3] as u16
    def cfg(policy, trigger, count=12):
        p = bytes([policy, trigger, 0])
        for _ in range(3):
            p += struct.pack("<H", 32768) + struct.pack("<H", 20000) + struct.pack("<3H", 32768, 32768, 32768)
        p += struct.pack("<4H", 30000, 6000, 3000, 20000) + bytes([count]) + struct.pack("<3H", 3300, 26000, 6554)
        for i in range(12):
            arm = [32768, 32768, 32768]
            arm[(i // 4) % 3] = 50000 if i % 2 == 0 else 15000
            arm[(i // 4 + 1) % 3] = 40000 if i % 4 < 2 else 25000
            p += struct.pack("<3H", *arm)
        return p

    def step(flags=7, h=(52000, 20000, 40000), b=(50000, 20000, 40000)):
        return bytes([flags]) + struct.pack("<3H", h[0], b[0], h[1]) + struct.pack("<3H", b[1], h[2], b[2])

    steps = b"".join(step(h=(52000 - 500 * k, 20000 + 300 * k, 40000)) for k in range(30))
    _write("fuzz_momentum_step", "magnetorquers_threshold", cfg(0, 0) + steps + step(flags=3) + step(flags=5))
    _write("fuzz_momentum_step", "magnetorquers_continuous", cfg(0, 1) + steps)
    _write("fuzz_momentum_step", "thrusters_threshold", cfg(1, 0) + steps + step(flags=6) + step(flags=1))
    _write("fuzz_momentum_step", "thrusters_few", cfg(1, 1, count=4) + steps)


def fdir_seeds() -> None:
    # fuzz_fdir_step: u8 setup, 4 x u16 parameters (wheel_residual_frac 0.1, st_chi2 16, st_frozen_rate 1e-4,
    # gyro_sat 0), 6 x u8 counts, u16 gyro_bias_chi2 (25), u8 gyro_bias_persist (3), u16 mom_residual_nm
    # (0.005, or 0 = no test), u8 mom_window, u8 mom_persist, u8 wheel_friction_window (10), u16
    # wheel_friction_excess (1), then steps: u8 flags,
    # u8 missing, 4 x (speed, command), chi2, gyro[3], q[4], u8 filter flags, bias[3], P bias diagonal[3], sigma_u
    def u16(v, lo, hi):
        return struct.pack("<H", min(65535, int((v - lo) / (hi - lo) * 65536)))

    def cfg(setup, mom_residual=0.0):
        return (bytes([setup]) + struct.pack("<4H", 5461, 10486, 655, 5958) + bytes([5, 5, 6, 5, 5, 3])
                + u16(25.0, -1.0, 50.0) + bytes([3]) + u16(mom_residual, 0.0, 5.0e-2) + bytes([4, 2])
                + bytes([10]) + u16(1.0, 0.0, 3.0))

    def step(flags=1 | 2 | 8 | 4 | 128, speeds=(100.0, -50.0, 30.0, 10.0), cmds=(0.0, 0.2, 0.0, 0.0), chi2=3.0,
             gyro=(1e-3, 2e-3, -1e-3), q=(0.0, 0.0, 0.0, 1.0), missing=0, applied=0, bias=(0.0, 0.0, 0.0),
             p_bias=4.0e-15, rrw=1.0e-10, z=(0.5, -0.5, 1.0)):
        b = bytes([flags, missing])
        for sp, u in zip(speeds, cmds):
            b += u16(sp, -700.0, 700.0) + u16(u, -0.3, 0.3)
        b += u16(chi2, 0.0, 50.0) + b"".join(u16(g, -1.0, 1.0) for g in gyro) + b"".join(u16(x, -1.0, 1.0) for x in q)
        b += bytes([applied]) + b"".join(u16(x, -1.0e-4, 1.0e-4) for x in bias)
        b += u16(p_bias, 0.0, 1.0e-10) * 3 + u16(rrw, 0.0, 1.0e-8)
        b += b"".join(u16(x, -30.0, 30.0) for x in z)
        return b

    # wheel 1 commanded 0.2 N m and not moving: isolated (four wheels), refused (three healthy)
    dead = b"".join(step(gyro=(1e-3 * k, 2e-3, -1e-3), q=(0.01 * k, 0.0, 0.0, 1.0)) for k in range(12))
    _write("fuzz_fdir_step", "wheel_dies", cfg(0) + dead)
    _write("fuzz_fdir_step", "wheel_dies_three_left", cfg(1) + dead)
    # innovation above the threshold, then consistent: excluded and restored; a frozen tracker; a gap
    st = b"".join(step(cmds=(0.0,) * 4, chi2=40.0) for _ in range(6)) + b"".join(
        step(cmds=(0.0,) * 4, chi2=2.0) for _ in range(8)) + b"".join(
        step(cmds=(0.0,) * 4, gyro=(1e-2, 0.0, 0.0)) for _ in range(6)) + step(flags=0) * 4 + step(missing=4)
    _write("fuzz_fdir_step", "star_tracker_and_link", cfg(0) + st)
    _write("fuzz_fdir_step", "disabled", cfg(2) + dead + st)
    # applied samples, the bias estimate steady, then 1e-6 rad/s off (z about 125 against 25): a bias jump
    bias = b"".join(step(cmds=(0.0,) * 4, applied=1, bias=(1e-7, 0.0, 0.0)) for _ in range(5)) + b"".join(
        step(cmds=(0.0,) * 4, applied=1, bias=(1.1e-6, 0.0, 0.0)) for _ in range(6))
    _write("fuzz_fdir_step", "gyro_bias_jump", cfg(0) + bias)
    # wheels holding 25 N m s (a dump starts) whose momentum does not change: the commanded impulse is missing
    # (thruster_ineffective, the dump switched off the thruster), then a momentum jump no thruster explains
    dump = b"".join(step(flags=1 | 2 | 8 | 32, speeds=(150.0, 150.0, 150.0, 150.0), cmds=(0.0,) * 4) for _ in range(14))
    jump = b"".join(step(flags=1 | 2 | 8 | 32, speeds=(150.0 + 20.0 * k, 150.0, 150.0, 150.0), cmds=(0.0,) * 4)
                    for k in range(14))
    _write("fuzz_fdir_step", "thruster_ineffective", cfg(0, 0.005) + dump + jump)
    # the gyro pinned at 1e-3 rad/s on every axis while the tracker turns 0.02 rad per sample, its innovations
    # failing: the tracker excluded, then the gyro named stuck and the tracker restored
    pinned = b"".join(step(cmds=(0.0,) * 4, chi2=40.0, gyro=(1e-3, 1e-3, 1e-3), q=(0.01 * k, 0.0, 0.0, 1.0))
                      for k in range(14))
    _write("fuzz_fdir_step", "gyro_pinned", cfg(0) + pinned)
    # the same with an estimator that can fly without the gyro (setup bit3): estimator_gyroless, no SAFE latched
    _write("fuzz_fdir_step", "gyro_pinned_gyroless", cfg(8) + pinned)
    # a tracker 10 times noisier than its model (white, spread about 100): excluded at the 5th sample, re-admitted
    # with its noise scaled at the end of its window (fdir.st_restore 6 here); then its noise back: scaled back
    signs = [(1, -1, 1), (-1, 1, 1), (1, 1, -1), (-1, -1, -1), (1, -1, -1), (-1, 1, -1)]
    noisy = b"".join(step(cmds=(0.0,) * 4, chi2=300.0, z=tuple(10.0 * s * (1 + 0.3 * (k % 3)) for s in signs[k % 6]))
                     for k in range(14))
    calm = b"".join(step(cmds=(0.0,) * 4, chi2=0.01, z=tuple(0.1 * s for s in signs[k % 6])) for k in range(8))
    _write("fuzz_fdir_step", "st_noise_rescaled", cfg(0) + noisy + calm)
    # wheel 0 at 100 rad/s, uncommanded, slowing by one speed quantum (1400 / 65536 rad/s) a period: 5.7 times
    # the friction model's 3 mN m (the residual 14 mN m, below the 25 mN m isolation threshold): at the end of
    # the 10-step friction window wheel_friction_high, the model rescaled
    q = 1400.0 / 65536.0
    friction = b"".join(step(cmds=(0.0,) * 4, speeds=(100.0 - q * k, 0.0, 0.0, 0.0)) for k in range(24))
    _write("fuzz_fdir_step", "wheel_friction_high", cfg(0) + friction)
    # a thruster stuck open (docs/spec.md 5.15.8), in raw f64 values (the u16 quantum of a rate is 3e-5 rad/s,
    # 0.06 N m s about x, far above the period's bound): the body's x rate grows by the +x couple's 1.2 N m over
    # each 0.1 s period, the wheels and the attitude still, no dump (STANDBY). Three periods name thruster 0:
    # thruster_stuck_open, branch A closed; the rate still growing names its twin 1: A reopened, B closed; still
    # growing: B reopened, both tried. Then the same with the growth stopping after A closes: a consistent
    # window (4 periods) isolates thruster 0 behind valve A.
    def raw_step(w_x):
        b = bytes([1 | 2 | 8 | 16, 0])
        b += struct.pack("<8d", 100.0, 0.0, -50.0, 0.0, 30.0, 0.0, 10.0, 0.0)
        b += struct.pack("<d", 3.0) + struct.pack("<3d", w_x, 0.0, 0.0) + struct.pack("<4d", 0.0, 0.0, 0.0, 1.0)
        b += bytes([0]) + struct.pack("<3d", 0.0, 0.0, 0.0) + struct.pack("<3d", 4.0e-15, 4.0e-15, 4.0e-15)
        b += struct.pack("<d", 1.0e-10) + struct.pack("<3d", 0.5, -0.5, 1.0)
        return b

    dw = 1.2 * 0.1 / 2059.5        # the stuck thruster's rate increment per period, rad/s
    growing = b"".join(raw_step(dw * k) for k in range(14))
    _write("fuzz_fdir_step", "thruster_stuck_open_swapped", cfg(0, 0.005) + growing)
    stopped = b"".join(raw_step(dw * min(k, 5)) for k in range(16))
    _write("fuzz_fdir_step", "thruster_stuck_open_isolated", cfg(0, 0.005) + stopped)


def pil_seeds() -> None:
    fr = frame
    step = fr.encode_step(1, 100_000_000, 3, Q, W, (0, 0, 0), (0, 0, 0))
    _write("fuzz_pil_frame", "step", fr.encode(fr.T_STEP, 1, step))
    step_st = fr.encode_step(2, 200_000_000, 3 | 8 | 16, Q, W, (0, 0, 0), (0, 0, 0), st_q=Q, st_t_meas_ns=100_000_000,
                             gyro_w=W)
    _write("fuzz_pil_frame", "step_star_tracker_gyro", fr.encode(fr.T_STEP, 2, step_st))
    step_mag = fr.encode_step(3, 300_000_000, 3 | 32, Q, W, (0, 0, 0), (0, 0, 0), mag_b_t=(2e-5, -1e-5, 3e-6))
    _write("fuzz_pil_frame", "step_magnetometer", fr.encode(fr.T_STEP, 3, step_mag))
    _write("fuzz_pil_frame", "select", fr.encode(fr.T_SELECT, 2, fr.encode_select(2, Q)))
    cfg = fr.ConfigFields()
    cfg.add("LAW", 2)
    cfg.add("QUAT_PD_KP", 4.0)
    cfg.add("QUAT_PD_KD", 8.0)
    cfg.add("U_MAX_AXIS", [0.5, 0.6, 0.7])
    cfg.add("HINF_TABLE", "hinf_regional")
    _write("fuzz_pil_frame", "config", fr.encode(fr.T_CONFIG, 0, cfg.encode()))
    _write("fuzz_pil_frame", "config_payload", cfg.encode())
    wcfg = fr.ConfigFields()
    wcfg.add("LAW", 2)
    wcfg.add("WHEELS_COUNT", 4)
    wcfg.add("WHEELS_NULL_GAIN", 0.02)
    for i in range(4):
        wcfg.add(f"WHEEL{i}_AXIS", [0.57735, 0.8165 if i == 0 else 0.0, 0.0])
        wcfg.add(f"WHEEL{i}_COULOMB", 2e-3)
    _write("fuzz_pil_frame", "config_wheels", fr.encode(fr.T_CONFIG, 0, wcfg.encode()))
    _write("fuzz_pil_frame", "hello", fr.encode(fr.T_HELLO, 0, fr.HELLO.pack(1, 4, 7, 1, 10, 10, 3)))
    _write("fuzz_pil_frame", "bye", fr.encode(fr.T_BYE, 9))
    _write("fuzz_pil_frame", "bad_crc", fr.encode(fr.T_STEP, 1, step)[:-1] + b"\0")


def direct_seeds(t) -> None:
    """fuzz_node_direct: (kind u8: 0 sensors_t, 1 command_t; u16 length; payload) chunks, the plant's order."""
    s, c = t.sensors_t, t.command_t

    def sensors(k, valid=s.VALID_ATTITUDE | s.VALID_RATE):
        m = s()
        m.protocol_version, m.frame, m.utime, m.tick, m.t_s, m.valid = s.PROTOCOL_VERSION, k, k * 100000, k, 0.1 * k, valid
        m.q, m.w, m.pos, m.vel = list(Q), list(W), [0.0] * 3, [0.0] * 3
        return m.encode()

    def cmd(request, law_id=c.LAW_KEEP, mode=c.MODE_KEEP):
        m = c()
        m.protocol_version, m.frame, m.utime, m.request = c.PROTOCOL_VERSION, request, 0, request
        m.law_id, m.mode, m.set_target, m.qd, m.wd = law_id, mode, False, [0.0, 0.0, 0.0, 1.0], [0.0] * 3
        return m.encode()

    def chunks(items) -> bytes:
        return b"".join(bytes([kind]) + struct.pack("<H", len(p)) + p for kind, p in items)

    good = [(0, sensors(k)) for k in range(8)]
    _write("fuzz_node_direct", "lockstep_good", chunks(good))
    _write("fuzz_node_direct", "commands_faults", chunks(good[:3] + [(1, cmd(1, mode=0)), (0, sensors(3)), (0, sensors(3)),
                                                            (0, b"\0\1garbage"), (1, cmd(2, mode=1)), (0, sensors(5)),
                                                            (0, sensors(6, valid=0)), (1, b"junk")] + good[7:]))


def main(argv: list[str]) -> int:
    build = Path(argv[1]) if len(argv) > 1 else REPO / "build" / "host"
    t = _bindings(build.resolve())
    sensors_seeds(t)
    command_seeds(t)
    direct_seeds(t)
    config_seeds()
    exec_seeds()
    mekf_seeds()
    momentum_seeds()
    fdir_seeds()
    pil_seeds()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
