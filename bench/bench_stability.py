"""Benchmark: overlapping Allan deviation of a 6-hour record at 1 kHz
(21.6 M samples) over all octave averaging times, igea against a numpy
cumulative-sum implementation, time and peak memory, in one run.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 .venv/bin/python bench/bench_stability.py [--n N]

Each method runs in its own child process on the same record (loaded from a
temporary .npy file); its extra peak memory is the growth of the child's
peak resident set (VmHWM) over the record alone.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

CHILD = r"""
import json, sys, time
import numpy as np

def hwm():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    return 0

path, method, fs = sys.argv[1], sys.argv[2], float(sys.argv[3])
y = np.load(path)
if method.startswith("igea"):
    import igea
    taus = igea.octave_taus(y.size, fs)
base = hwm()
t0 = time.perf_counter()
if method == "igea":
    dev = igea.allan(y, fs, taus, noise="wfm").dev
elif method == "igea-auto":
    dev = igea.allan(y, fs, taus, noise="auto").dev
else:
    n = y.size
    x = np.empty(n + 1)
    x[0] = 0.0
    np.cumsum(y - y.mean(), out=x[1:])
    ms, m = [], 1
    while n - 2 * m + 1 >= 1:
        ms.append(m)
        m *= 2
    dev = []
    for m in ms:
        d = x[2 * m:] - 2.0 * x[m:-m] + x[:-2 * m]
        dev.append(np.sqrt(np.dot(d, d) / d.size / (2.0 * m * m)))
    dev = np.array(dev)
el = time.perf_counter() - t0
print(json.dumps({"time": el, "extra": hwm() - base, "dev": list(map(float, dev))}))
"""


def run(path, method, fs):
    out = subprocess.run([sys.executable, "-c", CHILD, path, method, str(fs)],
                         capture_output=True, text=True, env=os.environ)
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=21_600_000, help="samples (default 6 h at 1 kHz)")
    ap.add_argument("--fs", type=float, default=1000.0)
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    # a gyro: 1 deg/h offset, white rate noise, a slow random walk
    y = 1.0 + rng.normal(0.0, 0.05, args.n) + np.cumsum(rng.normal(0.0, 1e-5, args.n))
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "record.npy")
        np.save(path, y)
        del y
        res = {m: run(path, m, args.fs) for m in ("numpy", "igea", "igea-auto")}
    d_np = np.array(res["numpy"]["dev"])
    d_ig = np.array(res["igea"]["dev"])
    print("overlapping Allan deviation, %d samples, %d octave taus" % (args.n, d_np.size))
    print("%-34s %10s %14s" % ("method", "time (s)", "extra peak MB"))
    for m, label in (("numpy", "numpy cumsum (reference)"), ("igea", "igea.allan, EDF white FM"),
                     ("igea-auto", "igea.allan, EDF noise auto")):
        print("%-34s %10.3f %14.1f" % (label, res[m]["time"], res[m]["extra"] / 2**20))
    print("speed ratio numpy / igea: %.2f (auto: %.2f)"
          % (res["numpy"]["time"] / res["igea"]["time"],
             res["numpy"]["time"] / res["igea-auto"]["time"]))
    print("extra memory numpy / igea: %.1f MB / %.1f MB"
          % (res["numpy"]["extra"] / 2**20, res["igea"]["extra"] / 2**20))
    print("max relative difference of the deviations: %.2e"
          % np.max(np.abs(d_ig / d_np - 1)))


if __name__ == "__main__":
    main()
