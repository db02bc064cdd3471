"""The Python conventions module (aocs_core.conventions) against the firmware it mirrors.

Every function of SPEC 1 that exists in both languages is evaluated on the same
random inputs by the C code (build/<preset>/bin/aocs_conventions, a host tool
linking the flight library) and by Python, and must agree to rounding (double
build) or to float precision (host-float build). Also the row (numpy) forms
against the scalar forms, and the one arcsec-per-radian constant.
"""
from __future__ import annotations

import math
import random
import subprocess

import numpy as np
import pytest

from aocs_analysis import metrics
from aocs_core import conventions as cv

N_CASES = 300


def _unit_quat(rng):
    q = [rng.gauss(0.0, 1.0) for _ in range(4)]
    n = math.sqrt(sum(x * x for x in q))
    return tuple(x / n for x in q)


@pytest.fixture(scope="module")
def c_eval(aocs_build_dir):
    exe = aocs_build_dir / "bin" / "aocs_conventions"
    if not exe.is_file():
        pytest.fail(f"{exe} missing: build the host preset (make build-host)")

    def run(lines: list[str]) -> list[list[float] | str]:
        out = subprocess.run([str(exe)], input="\n".join(lines) + "\n", capture_output=True, text=True,
                             timeout=60, check=True).stdout.splitlines()
        return out
    return run


@pytest.fixture(scope="module")
def tol(real_is_float):
    return 2e-6 if real_is_float else 1e-14


def _nums(line: str) -> list[float]:
    return [float(x) for x in line.split()]


def test_product_error_and_dcm_agree_with_the_firmware(c_eval, tol):
    rng = random.Random(20261201)
    cases = [(_unit_quat(rng), _unit_quat(rng)) for _ in range(N_CASES)]
    fmt = lambda v: " ".join(repr(x) for x in v)  # noqa: E731
    lines = [f"mul {fmt(q)} {fmt(p)}" for q, p in cases] + [f"err {fmt(q)} {fmt(p)}" for q, p in cases]
    lines += [f"dcm {fmt(q)}" for q, _ in cases]
    out = c_eval(lines)
    assert len(out) == 2 * N_CASES + 3 * N_CASES
    for i, (q, p) in enumerate(cases):
        assert np.allclose(_nums(out[i]), cv.quat_mul(q, p), rtol=0, atol=tol)
        assert np.allclose(_nums(out[N_CASES + i]), cv.quat_error(q, p), rtol=0, atol=tol)
        rows = [_nums(out[2 * N_CASES + 3 * i + r]) for r in range(3)]
        assert np.allclose(rows, cv.quat_to_dcm(q), rtol=0, atol=tol)
    # the defining property of the product (SPEC 1): A(q (x) p) = A(q) A(p)
    q, p = cases[0]
    assert np.allclose(np.array(cv.quat_to_dcm(cv.quat_mul(q, p))),
                       np.array(cv.quat_to_dcm(q)) @ np.array(cv.quat_to_dcm(p)), atol=1e-14)


def test_euler_crp_mrp_and_angle_agree_with_the_firmware(c_eval, tol):
    rng = random.Random(7)
    eul = [(rng.uniform(-math.pi, math.pi), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi))
           for _ in range(N_CASES)]
    quats = [_unit_quat(rng) for _ in range(N_CASES)]
    quats = [q for q in quats if abs(q[3]) > 1e-3]  # away from the CRP singularity
    fmt = lambda v: " ".join(repr(x) for x in v)  # noqa: E731
    lines = [f"e2q {fmt(e)}" for e in eul] + [f"q2e {fmt(cv.euler321_to_quat(*e))}" for e in eul]
    lines += [f"crp {fmt(q)}" for q in quats] + [f"mrp {fmt(q)}" for q in quats] + [f"angle {fmt(q)}" for q in quats]
    out = c_eval(lines)
    n, m = len(eul), len(quats)
    for i, e in enumerate(eul):
        assert np.allclose(_nums(out[i]), cv.euler321_to_quat(*e), atol=tol)
        assert np.allclose(_nums(out[n + i]), e, atol=100 * tol)   # asin near pitch 1.5 amplifies rounding
        assert np.allclose(cv.quat_to_euler321(cv.euler321_to_quat(*e)), e, atol=1e-12)
    for i, q in enumerate(quats):
        rho = cv.quat_to_crp(q)
        assert np.allclose(_nums(out[2 * n + i]), rho, rtol=100 * tol, atol=tol)
        assert np.allclose(_nums(out[2 * n + m + i]), cv.quat_to_mrp(q), atol=tol)
        assert _nums(out[2 * n + 2 * m + i])[0] == pytest.approx(cv.pointing_error_rad(q, (0.0, 0.0, 0.0, 1.0)),
                                                                  abs=max(tol, 1e-7 if tol > 1e-10 else 1e-12))


def test_the_firmware_refuses_a_singular_gibbs_vector(c_eval):
    out = c_eval(["crp 1 0 0 0", "crp 0.6 0.8 0 1e-12"])
    assert out == ["singular", "singular"]


def test_malformed_requests_are_answered_not_fatal(c_eval):
    assert c_eval(["mul 1 2 3", "nonsense 1", "dcm 0 0 0 1"]) == ["error", "error", "1 0 0", "0 1 0", "0 0 1"]


def test_row_forms_match_the_scalar_forms():
    rng = random.Random(3)
    q = np.array([_unit_quat(rng) for _ in range(50)])
    p = np.array([_unit_quat(rng) for _ in range(50)])
    prod = cv.quat_mul_rows(q, p)
    for i in range(50):
        assert np.allclose(prod[i], cv.quat_mul(tuple(q[i]), tuple(p[i])), atol=1e-15)
    v = np.array([[rng.gauss(0, 1) for _ in range(3)] for _ in range(50)] + [[0.0, 0.0, 0.0]])
    rv = cv.quat_from_rotvec_rows(v)
    for i in range(len(v)):
        assert np.allclose(rv[i], cv.quat_from_rotvec(tuple(v[i])), atol=1e-15)
    err = cv.quat_error_rows(q, p[0])
    assert np.all(err[:, 3] >= 0.0)


def test_one_arcsec_per_radian_everywhere():
    assert cv.ARCSEC_PER_RAD == 180.0 * 3600.0 / math.pi
    assert metrics.ARCSEC_PER_RAD is cv.ARCSEC_PER_RAD


def test_gibbs_and_mrp_inputs_beyond_the_square_overflow_stay_unit_and_finite():
    """Scenario inputs plant.rho = [1e160, 0, 0] or sigma = [1e200, 0, 0] (issue 11): no overflow to inf/NaN
    or division by zero; the same attitude as the limit of the formula (180 deg about x; identity for MRP)."""
    q = cv.crp_to_quat((1e160, 0.0, 0.0))
    assert all(math.isfinite(x) for x in q) and math.isclose(cv.quat_norm(q), 1.0, rel_tol=1e-15)
    assert q[0] == 1.0 and 0.0 < q[3] < 1e-150
    q = cv.crp_to_quat((3e200, -4e200, 0.0))
    assert q[:3] == pytest.approx((0.6, -0.8, 0.0), rel=1e-15) and math.isclose(cv.quat_norm(q), 1.0, rel_tol=1e-15)
    for sigma in ((1e200, 0.0, 0.0), (1e160, -1e160, 5e159)):
        q = cv.mrp_to_quat(sigma)
        assert all(math.isfinite(x) for x in q) and math.isclose(cv.quat_norm(q), 1.0, rel_tol=1e-15)
        assert abs(q[3]) == pytest.approx(1.0)
    # below the overflow the formulas are untouched, bit for bit
    assert cv.crp_to_quat((-10.0, 15.0, 15.0)) == tuple(x / math.sqrt(1.0 + 550.0) for x in (-10.0, 15.0, 15.0, 1.0))
    assert cv.mrp_to_quat((3.0, 0.0, 0.0)) == (0.6, 0.0, 0.0, -0.8)
