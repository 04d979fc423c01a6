#!/usr/bin/env python3
"""Seed 002's navigation comparisons (Figs. 9-11) on simulated data with
stated sensor errors (docs/redundancy.md, "Navigation with the redundant
IMU").

Fig. 9 - a 0.5 h flight: the reference boost of igea_sim_trajectory (300 s
at 10 Hz, strapdown) with its specific force scaled by 1.312 (thrust 19.7 to
32.8 m/s^2, burnout at 5.3 km/s) then free flight (zero increments) to
1800 s, when it is back on the ground (apogee 1600 km), launch at 40 N
100 E, azimuth 60 deg, J2; the 1-sigma position error (the root of the
trace of the position block of igea.nav_errors_li's covariance) from random
constant accelerometer biases and gyro drifts of a non-redundant IMU (one
sensor per axis) and of the fused redundant IMU of seed 002 (4 X
accelerometers, 2 Y, 2 Z, 2 gyros per axis, the fused bias of n
independent sensors having variance sigma^2 / n), and the ratio against the
number of fused X accelerometers.

Figs. 10-11 - a 6 h static run at 40 N with the IMU's X-Y-Z axes along
north-up-east (the seed's set-up): the east position error and the azimuth
error (igea.nav_errors, Earth rate on) of each of the four virtual IMUs of
igea.redund_group's grouping and of the fused IMU, from one draw of the
sensors' constant biases (seed 2).

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \
        .venv/bin/python bench/redund_navigation.py

Prints the figures' numbers; with matplotlib, writes docs/redund_fig9.png
and docs/redund_fig10_11.png.
"""
import math
import os

import numpy as np

import igea

HERE = os.path.dirname(os.path.abspath(__file__))
DEG = math.pi / 180.0
UG = 9.80665e-6            # 1 micro-g, m/s^2
DPH = DEG / 3600.0         # 1 deg/h, rad/s

# stated 1-sigma sensor errors (constant over the run)
ACC_X, ACC_YZ = 60 * UG, 20 * UG        # accelerometer biases
GYRO = 0.01 * DPH                       # gyro drifts


def flight_record(boost=300.0, total=1800.0, rate=10.0, thrust=1.312):
    """The 0.5 h strapdown telemetry (rows t dv dth) and q0: the reference
    boost with its force scaled by thrust, trapezoid increments, then free
    flight at 1 Hz."""
    traj = np.asarray(igea.reference_trajectory(boost, rate))
    t = traj[:, 0]
    h = np.diff(t)[:, None]
    tel = np.zeros((len(t), 7))
    tel[:, 0] = t
    tel[1:, 1:4] = thrust * h * (traj[:-1, 1:4] + traj[1:, 1:4]) / 2
    tel[1:, 4:7] = h * (traj[:-1, 4:7] + traj[1:, 4:7]) / 2
    coast = np.zeros((int(total - boost), 7))
    coast[:, 0] = boost + np.arange(1, len(coast) + 1)
    return np.vstack([tel, coast]), traj[0, 7:11].copy()


def bias_variances(nx=1, nyz=1, ng=1):
    """The diagonal P0 of the constant sensor errors (slots 9..14) of an
    IMU whose X channel fuses nx accelerometers, Y and Z nyz each, and each
    gyro channel ng gyros: sigma^2 / n."""
    P0 = np.zeros((15, 15))
    v = [ACC_X ** 2 / nx, ACC_YZ ** 2 / nyz, ACC_YZ ** 2 / nyz] + [GYRO ** 2 / ng] * 3
    P0[range(9, 15), range(9, 15)] = v
    return P0


def position_sigma(site, tel, q0, P0, epochs):
    r = igea.nav_errors_li(site, tel, q0=q0, epochs=epochs, q=np.zeros(12), p0=P0)
    return np.sqrt(np.trace(r.covariance[:, 0:3, 0:3], axis1=1, axis2=2))


def fig9(step=60.0):
    site = igea.nav_site(40 * DEG, 100 * DEG, 0.0, 60 * DEG)
    tel, q0 = flight_record()
    ep = np.r_[0.0, np.arange(step, 1800.0 + 1e-9, step)]
    single = position_sigma(site, tel, q0, bias_variances(), ep)
    fused = position_sigma(site, tel, q0, bias_variances(4, 2, 2), ep)
    ratios = [single[-1] / position_sigma(site, tel, q0, bias_variances(n), ep[-1:])[-1]
              for n in (1, 2, 3, 4)]
    only_x = bias_variances()
    only_x[range(10, 15), range(10, 15)] = 0.0
    px = position_sigma(site, tel, q0, only_x, ep[-1:])[-1] ** 2
    return ep, single, fused, ratios, px, single[-1] ** 2 - px


def closed_ratio(n, px, pr):
    """The ratio of the position sigmas when the X bias variance is divided
    by n: sqrt((px + pr) / (px / n + pr)), px the variance the X bias alone
    gives, pr the others' (the covariance is linear in P0)."""
    return math.sqrt((px + pr) / (px / n + pr))


def static_errors(seed=2, lat=40.0, hours=6.0):
    """East error and azimuth error of each group and fused: X-Y-Z = N-U-E,
    so a body error (x, y, z) is (x, z, -y) in north-east-down."""
    rng = np.random.default_rng(seed)
    acc = np.r_[ACC_X * rng.standard_normal(4), ACC_YZ * rng.standard_normal(4)]  # Ax1-4 Ay1 Ay2 Az1 Az2
    gyro = GYRO * rng.standard_normal(6)                                          # Gx1 Gx2 Gy1 Gy2 Gz1 Gz2
    groups = igea.redund.SEED002_GROUPS
    gyro_of = [(0, 2, 4), (1, 3, 5), (0, 2, 4), (1, 3, 5)]
    ned = lambda v: np.array([v[0], v[2], -v[1]])  # noqa: E731
    runs = {}
    for g in range(4):
        runs["group %d" % (g + 1)] = (ned(acc[list(groups[g])]), ned(gyro[list(gyro_of[g])]))
    fa = np.array([acc[0:4].mean(), acc[4:6].mean(), acc[6:8].mean()])
    fg = np.array([gyro[0:2].mean(), gyro[2:4].mean(), gyro[4:6].mean()])
    runs["fused"] = (ned(fa), ned(fg))
    out = {}
    for name, (b, e) in runs.items():
        r = igea.nav_errors(lat=lat, duration=hours * 3600, epochs=361, acc_bias=b, gyro_drift=e)
        out[name] = (r.time, r.position[:, 1], r.attitude[:, 2])
    return out


def main():
    ep, single, fused, ratios, px, pr = fig9()
    print("Fig. 9: position error at 1800 s: non-redundant %.0f m, fused %.0f m, ratio %.3f"
          % (single[-1], fused[-1], single[-1] / fused[-1]))
    print("ratio against the number of fused X accelerometers 1..4: "
          + ", ".join("%.3f" % r for r in ratios) + " (closed form "
          + ", ".join("%.3f" % closed_ratio(n, px, pr) for n in (1, 2, 3, 4))
          + "; the X bias's share of the variance %.3f)" % (px / (px + pr)))
    st = static_errors()
    for name, (t, de, az) in st.items():
        print("6 h static, %-8s: east %8.1f m (max |.| %7.1f), azimuth %8.2f arcmin"
              % (name, de[-1], np.max(np.abs(de)), az[-1] / DEG * 60))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(ep / 60, single, label="non-redundant IMU")
    ax[0].plot(ep / 60, fused, label="fused redundant IMU")
    ax[0].set_xlabel("time of flight (min)")
    ax[0].set_ylabel("1-sigma position error (m)")
    ax[0].legend()
    ax[0].set_title("0.5 h flight (cf. seed 002 Fig. 9)")
    ax[1].plot([1, 2, 3, 4], ratios, "o", label="covariance runs")
    nn = np.linspace(1, 4, 61)
    ax[1].plot(nn, [closed_ratio(n, px, pr) for n in nn], "-",
               label="sqrt((Px + Pr) / (Px / n + Pr))")
    ax[1].plot(nn, np.sqrt(nn), ":", label="sqrt(n): X alone")
    ax[1].legend(fontsize=8)
    ax[1].set_xlabel("fused X accelerometers")
    ax[1].set_ylabel("non-redundant / fused error at 1800 s")
    ax[1].set_title("ratio against the number of X sensors")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "..", "docs", "redund_fig9.png"), dpi=100)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for name, (t, de, az) in st.items():
        lw = 2.5 if name == "fused" else 1.0
        ax[0].plot(t / 3600, -np.abs(de), lw=lw, label=name)
        ax[1].plot(t / 3600, np.abs(az) / DEG * 60, lw=lw, label=name)
    ax[0].set_ylabel("east error (m, drawn negative)")
    ax[1].set_ylabel("azimuth error (arcmin, drawn positive)")
    for a in ax:
        a.set_xlabel("time (h)")
        a.legend(fontsize=8)
    ax[0].set_title("6 h static (cf. seed 002 Fig. 10)")
    ax[1].set_title("6 h static (cf. seed 002 Fig. 11)")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "..", "docs", "redund_fig10_11.png"), dpi=100)


if __name__ == "__main__":
    main()
