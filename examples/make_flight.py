#!/usr/bin/env python3
"""Writes examples/flight/: a synthetic 120 s boost flight of a platform
inertial system with 18 error terms, for 'make demo' and the README.

Environment functions follow METHODS 5.3 (platform system, launch-inertial
axes): accelerometer bias t e_j, scale factor W_j(t) e_j, gyro drift
t (W x e_j) - int W x e_j dt, second-order accelerometer int f_j^2 dt e_j,
g-sensitive gyro drift int W_j (f x e_j) dt, initial alignment W(t) x e_k, integrated with
the trapezoid rule at 10 Hz and sampled at 1 Hz tracking epochs (rows
epoch-major x, y, z). The true errors are drawn N(0, I) in spec units with a
fixed seed; tracking noise is white with stated sigma 0.01 m/s and a true
scale sigma_w = 1.3, which the sigma_w correction should find.

    python3 examples/make_flight.py [outdir]      (needs numpy)
"""
import os
import sys

import numpy as np

G0 = 9.80665
rate, T, sigma_track, sigma_w, seed = 10.0, 120.0, 0.01, 1.3, 20181

t = np.arange(0.0, T + 1e-9, 1.0 / rate)
# specific force in launch-inertial axes: thrust ramp 15 -> 25 m/s^2,
# pitch-over from vertical (y up) towards x, a small wobble in z
pitch = np.deg2rad(90.0 - 50.0 * np.clip((t - 10.0) / 100.0, 0.0, 1.0))
thrust = 15.0 + 10.0 * t / T
f = np.stack([thrust * np.cos(pitch), thrust * np.sin(pitch), 0.3 * np.sin(0.5 * t)], axis=1)


def cumtrapz(y):
    out = np.zeros_like(y)
    out[1:] = np.cumsum(0.5 * (y[1:] + y[:-1]) / rate, axis=0)
    return out


W = cumtrapz(f)                                   # apparent velocity
E = np.eye(3)
cols, names = [], []
for j, a in enumerate("xyz"):
    cols.append(t[:, None] * E[j]); names.append(f"acc_bias_{a}")
for j, a in enumerate("xyz"):
    cols.append(W[:, j:j + 1] * E[j]); names.append(f"acc_scale_{a}")
for j, a in enumerate("xyz"):
    WxE = np.cross(W, E[j])
    cols.append(t[:, None] * WxE - cumtrapz(WxE)); names.append(f"gyro_bias_{a}")
for j, a in enumerate("xyz"):
    cols.append(cumtrapz(f[:, j:j + 1] ** 2) * E[j]); names.append(f"acc_sq_{a}")
for j, a in enumerate("xyz"):
    cols.append(cumtrapz(W[:, j:j + 1] * np.cross(f, E[j]))); names.append(f"gyro_gi_{a}")
for k, a in enumerate("xyz"):
    cols.append(np.cross(W, E[k])); names.append(f"align0_{a}")
spec = np.array([1e-3 * G0] * 3 + [1e-4] * 3 + [np.deg2rad(0.5) / 3600] * 3 + [2e-5 / G0] * 3
                + [np.deg2rad(0.5) / 3600 / G0] * 3 + [1e-4] * 3)

epochs = np.arange(int(rate), len(t), int(rate))   # 1 Hz, t = 1..120 s
S = np.stack([c[epochs] for c in cols], axis=2).reshape(-1, len(cols))   # (3M, N) epoch-major
rng = np.random.default_rng(seed)
X = rng.standard_normal(len(cols))                 # in spec units
sigma = np.full(S.shape[0], sigma_track)
dw = S @ (X * spec) + sigma_w * sigma * rng.standard_normal(S.shape[0])

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "flight")
os.makedirs(out, exist_ok=True)
hdr = "synthetic 120 s platform flight (examples/make_flight.py, seed %d)" % seed
np.savetxt(os.path.join(out, "S.txt"), S, fmt="%.17g",
           header=hdr + "\nrows epoch-major x,y,z at t = 1..120 s; columns: " + " ".join(names))
np.savetxt(os.path.join(out, "dw.txt"), dw, fmt="%.17g", header=hdr + "\nvelocity differences, m/s")
np.savetxt(os.path.join(out, "sigma.txt"), sigma, fmt="%.17g", header=hdr + "\nstated tracking 1-sigma, m/s")
np.savetxt(os.path.join(out, "spec.txt"), spec, fmt="%.17g", header=hdr + "\n1-sigma specs: " + " ".join(names))
np.savetxt(os.path.join(out, "X_true.txt"), X, fmt="%.17g", header=hdr + "\ntrue errors in spec units; true sigma_w = %g" % sigma_w)
print("wrote", out, S.shape)
