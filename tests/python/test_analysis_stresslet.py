"""analysis.stresslet (eqs. 4.12-4.15) and analysis.averages on synthetic data."""

import math

import numpy as np
import pytest

from analysis import averages, stresslet
from analysis.statistics import standard_error


def tensor(s1, s2, theta_deg, s3=0.0):
    """A stresslet with in-plane principal values s1 >= s2, S1's axis at theta from x."""
    t = math.radians(theta_deg)
    r = np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])
    return r @ np.diag([s1, s2, s3]) @ r.T


@pytest.mark.parametrize("theta", [30.0, -20.0, 89.0, 1.0])
def test_principal_in_plane_recovers_construction(theta):
    s1, s2, th = stresslet.principal_in_plane(tensor(2.5, -0.7, theta, 0.3))
    assert (s1, s2, th) == pytest.approx((2.5, -0.7, theta))


def test_principal_angle_range_and_batch():
    batch = np.stack([tensor(1.0, 0.0, 90.0), tensor(1.0, 0.0, 45.0)])
    _, _, th = stresslet.principal_in_plane(batch)
    assert th == pytest.approx([90.0, 45.0])


def test_eqs_4_12_and_4_13_hold_for_one_tensor():
    s = tensor(3.0, 1.0, 25.0)
    s1, s2, th = stresslet.principal_in_plane(s)
    assert stresslet.shear_component(s1 - s2, th) == pytest.approx(s[0, 1])
    assert stresslet.normal_difference(s1 - s2, th) == pytest.approx(s[0, 0] - s[1, 1])


def test_decomposition_exact_for_aligned_ensemble_and_biased_for_spread_angles():
    same = stresslet.decomposition(tensor(3.0, 1.0, 25.0), 2.0, 25.0)
    assert same["S12_principal"] == pytest.approx(same["S12"])
    assert same["S11_S22_principal"] == pytest.approx(same["S11_S22"])
    # Two capsules at 20 and 30 degrees: the mean tensor's S12 = mean of sin terms, which
    # differs from sin(2 <theta>) by the factor cos(10 deg) (eq. 4.14 is approximate).
    pair = [tensor(2.0, 0.0, 20.0), tensor(2.0, 0.0, 30.0)]
    d = stresslet.decomposition(np.mean(pair, axis=0), 2.0, 25.0)
    assert d["S12"] == pytest.approx(d["S12_principal"] * math.cos(math.radians(10)))
    assert d["sin2theta_S"] == pytest.approx(math.sin(math.radians(50)))


def synthetic_series():
    time = np.arange(0.0, 20.01, 1.0)
    n, m = time.size, 2
    d = np.stack([0.01 * time, 0.01 * time + 0.1], axis=1)
    s = np.zeros((n, m, 3, 3))
    s[..., 0, 1] = s[..., 1, 0] = 1.0
    return {"time": time, "D": d, "theta_D_deg": np.full((n, m), 30.0),
            "principal_diff": np.full((n, m), 2.0), "theta_S_deg": np.full((n, m), 45.0),
            "stresslet": s}


def test_run_averages_from_t_s():
    avg = averages.run_averages(synthetic_series(), t_start=10.0)
    # t = 10..20 (11 samples): capsule 0 mean 0.15, capsule 1 mean 0.25 -> 0.2
    assert avg["D"] == pytest.approx(0.2)
    assert avg["count"] == 22
    assert avg["t_end"] == 20.0
    assert avg["theta_D_std_deg"] == pytest.approx(0.0)
    assert avg["theta_D_std_se_deg"] == 0.0 and avg["D_std_se"] > 0
    assert avg["stresslet"][0, 1] == pytest.approx(1.0)
    var = np.var(np.concatenate([0.01 * np.arange(10, 21), 0.01 * np.arange(10, 21) + 0.1]))
    assert avg["D_std"] == pytest.approx(math.sqrt(var))


def test_running_average_of_a_ramp():
    ts = synthetic_series()
    out = averages.running_average(ts["D"][:, 0], ts["time"], 10.0, [10.0, 14.0, 20.0, 5.0])
    assert out[:3] == pytest.approx([0.10, 0.12, 0.15])
    assert math.isnan(averages.running_average(ts["D"], ts["time"], 30.0, [31.0])[0])


def test_ensemble_mean_and_std():
    mean, std = averages.ensemble([0.37, 0.38, 0.39])
    assert mean == pytest.approx(0.38)
    assert std == pytest.approx(math.sqrt(2 / 3) * 0.01)
    assert averages.ensemble([1.0, 3.0], ddof=1)[1] == pytest.approx(math.sqrt(2))
    assert averages.ensemble([1.0], ddof=1)[1] == 0.0


def test_decomposition_standard_errors_follow_the_linearised_series():
    # theta_S constant at 30 deg: eq. 4.14's right-hand side varies only with S1 - S2, so
    # its standard error is 1/2 sin 60 deg that of <S1 - S2>; sin 2<theta_S> has none.
    rng = np.random.default_rng(7)
    ts = synthetic_series()
    ts["principal_diff"] = 2.0 + 0.1 * rng.standard_normal(ts["principal_diff"].shape)
    ts["theta_S_deg"] = np.full_like(ts["principal_diff"], 30.0)
    avg = averages.run_averages(ts, t_start=0.0)
    se = avg["decomposition_se"]
    assert avg["principal_diff_se"] > 0
    assert se["S12_principal"] == pytest.approx(0.5 * math.sin(math.radians(60))
                                                * avg["principal_diff_se"])
    assert se["S11_S22_principal"] == pytest.approx(0.5 * avg["principal_diff_se"])
    assert se["sin2theta_S"] == pytest.approx(0.0, abs=1e-12)
    # theta_S varying alone: d sin 2theta / dtheta = 2 cos 2theta per radian.
    ts["principal_diff"] = np.full_like(ts["principal_diff"], 2.0)
    ts["theta_S_deg"] = 30.0 + rng.standard_normal(ts["theta_S_deg"].shape)
    avg = averages.run_averages(ts, t_start=0.0)
    slope = 2.0 * math.cos(2.0 * math.radians(avg["theta_S_deg"])) * math.pi / 180.0
    assert avg["decomposition_se"]["sin2theta_S"] == pytest.approx(
        slope * avg["theta_S_se_deg"])


def test_running_standard_error():
    rng = np.random.default_rng(3)
    ts = synthetic_series()
    d = 0.3 + 0.01 * rng.standard_normal(ts["D"].shape)
    out = averages.running_standard_error(d, ts["time"], 10.0, [10.0, 15.0, 20.0])
    assert np.isnan(out[0])  # one sample
    assert out[2] == pytest.approx(standard_error(d, ts["time"], 10.0, 20.0))
