"""Coverage and bias of the IMU triad calibration by simulation
(docs/calibration.md, "Verification"): RECORDS simulated rotating IMUs with
known accelerometer and gyro parameters (tests/python/test_triad_gyro.py's
simulator: 30 random attitudes held 4 s after a 30-s start, 2-s rotations,
5 mm/s^2 and 2 mrad/s white noise at 100 Hz), each calibrated by
igea.triad_calibrate(acc, 100, gyro=...). For each of the 21 parameters:
the fraction of records whose estimate lies within 3 reported sds of the
truth, with its 99 % Clopper-Pearson interval, and the mean standardised
error (theta_hat - theta) / sd with its 99 % interval (+-2.576 / sqrt(N)).
The requirement: every fraction >= 0.99 and every |mean| <= 0.3. Beside it,
the rate the sds predict (t with 22 degrees of freedom for the
accelerometer, 51 for the gyro: 0.9934 and 0.9958) and whether each 99 %
interval holds it: with exact sds a 500-record run still shows some
fraction below 0.99 with probability 0.74 (binomial; printed below).

  OPENBLAS_NUM_THREADS=1 PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 \\
    nice .venv/bin/python bench/triad_coverage.py [--records 500] [--seed 2026]

With --lat DEG the records are tests/python/test_triad_earth.py's
navigation-grade IMU at that latitude (the Earth's rate in every static
attitude and turn, a random heading; 50 ug and 3 urad/s noise, 5-s
attitudes), calibrated with lat=DEG; the heading found is checked as a
22nd estimate. With --lat DEG --without-lat each record is also calibrated
without lat= (the static mean taken as the bias) and the gyro biases'
errors are printed for both fits: rms error in rad/s and the largest and
median |error| / sd.

(500 records take about 2.5 minutes of CPU; --first K starts the seeds at
K, so that a larger study can be run in pieces and pooled with --merge.)
"""
import argparse
import importlib.util
import json
import math
import os
import time

import numpy as np
from scipy import stats

import igea

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location(
    "triad_sim", os.path.join(HERE, "..", "tests", "python", "test_triad_gyro.py"))
sim = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(sim)
_spec = importlib.util.spec_from_file_location(
    "triad_earth", os.path.join(HERE, "..", "tests", "python", "test_triad_earth.py"))
earth = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(earth)

NAMES = ["acc." + n for n in igea.triad.NAMES] + ["gyro." + n for n in igea.triad.GYRO_NAMES]


def run(records, seed, first, lat=None, without=False):
    z, failed, before = [], 0, []
    for i in range(first, first + records):
        rng = np.random.default_rng([seed, i])
        if lat is None:
            raw_a, raw_g, _ = sim.simulate(rng)
            truth_a, truth_g = sim.ACC, sim.GYR
        else:
            raw_a, raw_g, heading = earth.simulate(rng, lat)
            truth_a, truth_g = earth.ACC, earth.GYR
        try:
            r = igea.triad_calibrate(raw_a, sim.FS, gyro=raw_g, lat=lat)
        except igea.IgeaError:
            failed += 1
            continue
        zi = np.r_[(r.theta - truth_a) / r.sd, (r.gyro.theta - truth_g) / r.gyro.sd]
        if lat is not None:
            zi = np.r_[zi, ((r.gyro.heading - heading + 180) % 360 - 180) / r.gyro.heading_sd]
        if without:
            g0 = igea.triad_calibrate(raw_a, sim.FS, gyro=raw_g).gyro
            e, e0 = r.gyro.theta[:3] - truth_g[:3], g0.theta[:3] - truth_g[:3]
            before.append(np.r_[e, e / r.gyro.sd[:3], e0, e0 / g0.sd[:3],
                                (r.gyro.heading - heading + 180) % 360 - 180,
                                r.gyro.heading_sd])
        z.append(zi)
    return np.array(z), failed, np.array(before)


def report_before(b):
    """The gyro biases with and without the Earth's rate (--without-lat)."""
    print("gyro biases over %d records, fitted with lat= and without it:" % len(b))
    for label, e, z in (("with lat", b[:, 0:3], b[:, 3:6]), ("without", b[:, 6:9], b[:, 9:12])):
        print("  %-8s rms error %s rad/s; |error|/sd median %s, max %s" % (
            label, " ".join("%.2e" % v for v in np.sqrt(np.mean(e ** 2, axis=0))),
            " ".join("%.2f" % v for v in np.median(np.abs(z), axis=0)),
            " ".join("%.2f" % v for v in np.max(np.abs(z), axis=0))))
    print("  heading error rms %.4f deg, max |error| %.4f deg, mean heading_sd %.4f deg"
          % (np.sqrt(np.mean(b[:, 12] ** 2)), np.max(np.abs(b[:, 12])), b[:, 13].mean()))


def report(z, failed):
    n = len(z)
    lo_all = True
    print("%d records calibrated, %d refused" % (n, failed))
    print("%-12s %9s %19s %9s %19s" % ("parameter", "in 3 sd", "99 % CP interval", "mean z",
                                       "99 % interval"))
    half = 2.576 / math.sqrt(n)
    pred = [1 - 2 * stats.t.sf(3, 22)] * 9 + [1 - 2 * stats.t.sf(3, 51)] * 12
    names = NAMES + ["heading"] * (z.shape[1] - len(NAMES))
    pred += [1 - 2 * stats.norm.sf(3)] * (z.shape[1] - len(NAMES))
    held = 0
    for j, name in enumerate(names):
        k = int(np.sum(np.abs(z[:, j]) < 3))
        lo = stats.beta.ppf(0.005, k, n - k + 1) if k > 0 else 0.0
        hi = stats.beta.ppf(0.995, k + 1, n - k) if k < n else 1.0
        m = z[:, j].mean()
        ok = k / n >= 0.99 and abs(m) <= 0.3
        lo_all &= ok
        held += lo <= pred[j] <= hi
        print("%-12s %9.4f  [%.4f, %.4f] %9.3f  [%6.3f, %6.3f] %s"
              % (name, k / n, lo, hi, m, m - half, m + half, "" if ok else "<-- fails"))
    allowed = n - math.ceil(0.99 * n)  # failures a fraction >= 0.99 allows
    chance = 1 - math.prod(1 - stats.binom.sf(allowed, n, 1 - q) for q in pred)
    print("the predicted rate (%.4f acc, %.4f gyro) lies in %d of the %d 99 %% intervals; "
          "with exact sds some fraction falls below 0.99 with probability %.2f"
          % (pred[0], pred[20], held, len(names), chance))
    within = np.abs(z) < 3
    print("all %d estimates: %.4f within 3 sd; sd of z per parameter %.3f .. %.3f"
          % (z.size, within.mean(), z.std(axis=0).min(), z.std(axis=0).max()))
    print("requirement (every fraction >= 0.99, every |mean z| <= 0.3):",
          "met" if lo_all else "NOT met")
    return lo_all


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--records", type=int, default=500)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--save", help="write the standardised errors to this .npy")
    ap.add_argument("--merge", nargs="*", default=[], help=".npy files of earlier runs to pool")
    ap.add_argument("--lat", type=float, help="the navigation-grade records with the Earth's "
                    "rate at this latitude (deg), calibrated with lat=")
    ap.add_argument("--without-lat", action="store_true", help="with --lat: also fit each "
                    "record without the Earth's rate and compare the gyro biases")
    a = ap.parse_args()
    if a.without_lat and a.lat is None:
        ap.error("--without-lat needs --lat")
    t0 = time.process_time()
    z, failed, before = run(a.records, a.seed, a.first, a.lat, a.without_lat)
    if a.save:
        np.save(a.save, z)
    for f in a.merge:
        z = np.vstack([z, np.load(f)])
    report(z, failed)
    if a.without_lat and len(before):
        report_before(before)
    print("CPU %.1f s; load %s" % (time.process_time() - t0,
                                   json.dumps(os.getloadavg())))


if __name__ == "__main__":
    main()
