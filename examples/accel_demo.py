"""Dividing-head calibration of an orthogonal accelerometer pair (seed 003).

    PYTHONPATH=python python examples/accel_demo.py              # fit accel_dual.txt
    PYTHONPATH=python python examples/accel_demo.py --regenerate  # rewrite it first

accel_dual.txt is one simulated calibration in the seed's experiment format:
20 positions, the counter-clockwise run 0, 18, ..., 360 deg and then the
clockwise run back to 0 (42 readings), columns angle (deg), A output (g),
B output (g). Truth: METHODS 4.3's coefficients, installation angle 2e-4 rad,
1 arcsec head angle errors per reading, 1 micro-g output noise.

The same fits from the command line:
    igea accel --data examples/accel_dual.txt
    igea accel --method ebr --prior examples/accel_prior.txt --data examples/accel_dual.txt
    igea accel --model single --data examples/accel_dual.txt
"""
import os
import sys

import numpy as np

import igea

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "accel_dual.txt")
PRIOR = os.path.join(HERE, "accel_prior.txt")
# [KA0, KB0, kA1, kB1, eta, KA2, KB2, KAio, KBio] (METHODS 4.2 order), delta0
TRUTH = np.array([2e-4, -1.5e-4, 3e-4, -2e-4, 0.5e-4, 0.2e-4, -0.1e-4, 0.1e-4, -0.2e-4, 2e-4])
# historical spreads: biases, scale corrections, eta ~1e-4; K2 and cross-couplings ~1e-5
TAU = np.array([1e-4] * 5 + [1e-5] * 4)


def regenerate(seed=2026):
    ccw = np.arange(21) * 18.0
    angles = np.concatenate([ccw, ccw[::-1]])
    ya, yb = igea.accel_simulate(angles, TRUTH, head_sd_arcsec=1.0, noise_sd=1e-6, seed=seed)
    with open(DATA, "w") as f:
        f.write("# igea accel example: one simulated dividing-head calibration (seed 003 format)\n")
        f.write("# counter-clockwise run 0..360 deg, then clockwise 360..0; 1\" head errors,\n")
        f.write("# 1 micro-g noise. truth KA0 KB0 kA1 kB1 eta KA2 KB2 KAio KBio delta0 =\n")
        f.write("# " + " ".join("%.1e" % v for v in TRUTH) + "\n")
        f.write("# angle_deg  A_output_g  B_output_g\n")
        for a, u, v in zip(angles, ya, yb):
            f.write("%6.1f  %.12f  %.12f\n" % (a, u, v))
    with open(PRIOR, "w") as f:
        f.write("# EBR prior scales tau_j (historical spreads), KA0 KB0 kA1 kB1 eta KA2 KB2 "
                "KAio KBio\n")
        f.write(" ".join("%g" % v for v in TAU) + "\n")


def main():
    if "--regenerate" in sys.argv or not os.path.exists(DATA):
        regenerate()
    d = np.loadtxt(DATA)
    theta, ya, yb, count = igea.accel_merge(d[:, 0], d[:, 1], d[:, 2])
    print("%d readings -> %d positions (0 deg: %d readings)\n" % (len(d), len(theta), count[0]))
    print(igea.accel_analyze(theta).summary(), "\n")
    for kw in [dict(model="single"), dict(), dict(method="ebr"),
               dict(method="ebr", prior_scale=TAU)]:
        fit = igea.accel_fit(theta, ya, None if kw.get("model") == "single" else yb, **kw)
        print(fit.summary(), "\n")
    C = igea.accel_combinations()
    print("truth of the estimable combinations:",
          " ".join("%s=%.3e" % (n, v) for n, v in
                   zip(igea.accel.combination_names(), C.T @ TRUTH[:9])))


if __name__ == "__main__":
    main()
