"""Benchmarks, time and peak memory in one run:
1. overlapping Allan deviation of a 6-hour record at 1 kHz (21.6 M samples)
   over all octave averaging times, igea against a numpy cumulative-sum
   implementation;
2. every statistic igea shares with allantools (adev oadev mdev tdev hdev
   ohdev totdev mtotdev ttotdev htotdev theo1 mtie tierms, and the
   gap-resistant oadev against gradev) on the same 10^6-sample phase record
   (white FM), igea against allantools, with the ratios.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 .venv/bin/python bench/bench_stability.py [--n N] [--part allan|allantools|all]

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


# ---- 2. the statistics shared with allantools ----

AT_CHILD = r"""
import json, sys, time
import numpy as np

def hwm():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    return 0

path, lib, kind, n, ms = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5]
x = np.load(path)[:n]
ms = [int(v) for v in ms.split(",")]
if kind == "gradev":
    x = x.copy()
    x[::997] = np.nan                                  # gaps
if lib == "igea":
    import igea
else:
    import allantools
base = hwm()
t0 = time.perf_counter()
if lib == "igea":
    k = "oadev" if kind == "gradev" else kind
    taus = [0.75 * m if kind == "theo1" else float(m) for m in ms]
    r = igea.stability(x, 1.0, taus, kind=k, data_type="phase", noise="wfm")
    dev = r.dev
else:
    taus = [0.75 * m if kind == "theo1" else float(m) for m in ms]
    out = getattr(allantools, kind)(x, 1.0, "phase", taus)
    dev = out[1]
el = time.perf_counter() - t0
print(json.dumps({"time": el, "extra": hwm() - base, "dev": list(map(float, dev))}))
"""

# (kind, samples, averaging factors m): allantools' total family and theo1
# loop in Python per subsequence (about 0.3 ms each for mtotdev), so they
# run on a prefix of the record and a few m
AT_CASES = [(k, 10 ** 6, "1,4,16,64,256,1024")
            for k in ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtie",
                      "tierms", "gradev")] + \
           [("theo1", 10 ** 5, "4,16,64"), ("mtotdev", 10 ** 4, "1,4,16"),
            ("ttotdev", 10 ** 4, "1,4,16"), ("htotdev", 10 ** 4, "1,4,16")]


def run_at(path, lib, kind, n, ms):
    out = subprocess.run([sys.executable, "-c", AT_CHILD, path, lib, kind, str(n), ms],
                         capture_output=True, text=True, env=os.environ)
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout)


def bench_allantools():
    try:
        import allantools  # noqa: F401
    except ImportError:
        print("allantools is not installed: the comparison is skipped")
        return
    rng = np.random.default_rng(2)
    x = np.cumsum(rng.standard_normal(10 ** 6))          # phase of white FM, tau0 = 1 s
    print("statistics shared with allantools, phase data (white FM), %d samples" % x.size)
    print("%-8s %8s %-20s %10s %10s %8s %10s %10s %10s" %
          ("kind", "samples", "m", "igea s", "at s", "at/igea", "igea MB", "at MB", "max rel d"))
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "phase.npy")
        np.save(path, x)
        for kind, n, ms in AT_CASES:
            a = run_at(path, "igea", kind, n, ms)
            b = run_at(path, "allantools", kind, n, ms)
            da, db = np.array(a["dev"]), np.array(b["dev"])
            d = np.max(np.abs(da / db - 1)) if da.size == db.size else float("nan")
            print("%-8s %8d %-20s %10.4f %10.4f %8.1f %10.1f %10.1f %10.1e" %
                  (kind, n, ms, a["time"], b["time"], b["time"] / a["time"],
                   a["extra"] / 2 ** 20, b["extra"] / 2 ** 20, d))
    print("(htotdev: igea divides by Stable32's bias factor, allantools does not; max rel d nan:\n"
          " allantools returned other taus; the record's phase alone is 7.6 MB; MB: growth of the\n"
          " child's peak resident set over it; igea's times include the EDF and intervals)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=21_600_000, help="samples (default 6 h at 1 kHz)")
    ap.add_argument("--fs", type=float, default=1000.0)
    ap.add_argument("--part", choices=("allan", "allantools", "all"), default="all")
    args = ap.parse_args()
    if args.part != "allan":
        bench_allantools()
    if args.part == "allantools":
        return
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
