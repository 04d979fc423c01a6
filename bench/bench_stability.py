"""Benchmarks of the stability statistics, in one run:

1. the Allan deviation of a 6-hour record at 1 kHz (21.6 M samples) over
   its 24 octave averaging times (23 for the modified one): igea's one pass
   (noise type given and identified) against the bandwidth floor (one pass
   over the record, a numpy sum and a copy, measured in the same run; the
   floor of the issue is one such pass per tau, and every method's ratio to
   it and to a single pass is printed), the chunked numpy cumulative-sum
   peer and allantools; CPU seconds (user + sys) of child processes run
   interleaved, the minimum of the repeats, and the growth of each child's
   peak resident set over the loaded record;
2. the driver on the same record as a .npy file: `igea stability` streamed
   against the same run loading the record (`--gaps` forces the loading
   path), maximum resident set and CPU time (user + sys) from /usr/bin/time;
3. every statistic igea shares with allantools (adev oadev mdev tdev hdev
   ohdev totdev mtotdev ttotdev htotdev theo1 mtie tierms, and the
   gap-resistant oadev against gradev) on one 10^6-sample phase record.

    PYTHONPATH=python IGEA_LIBRARY=build/lib/libigea.so.1 IGEA_DRIVER=build/bin/igea \\
        .venv/bin/python bench/bench_stability.py [--n N] [--reps R] [--part allan|driver|allantools|all]

Threads: every child runs with OPENBLAS_NUM_THREADS=1 (igea's Allan pass is
single-threaded, numpy's sum and cumsum too). The machine may be shared:
CPU time, not wall time, is compared, and each ratio is of minima measured
in the same run.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")

CHILD = r"""
import json, resource, sys
import numpy as np

def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime

def hwm():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    return 0

path, method, fs = sys.argv[1], sys.argv[2], float(sys.argv[3])
y = np.load(path)
n = y.size
ms = []
m = 1
while n - 2 * m + 1 >= 1:
    ms.append(m)
    m *= 2
mm = [m for m in ms if n - 3 * m + 2 >= 1]
if method.startswith("igea"):
    import igea
elif method.startswith("allantools"):
    import allantools
base = hwm()
c0 = cpu()
if method == "sum":
    dev = [float(y.sum())]
elif method == "copy":
    z = y.copy()
    dev = [float(z[-1])]
elif method == "igea_o_wfm":
    dev = igea.allan(y, fs, np.array(ms) / fs, noise="wfm").dev
elif method == "igea_o_auto":
    dev = igea.allan(y, fs, np.array(ms) / fs, noise="auto").dev
elif method == "igea_m_wfm":
    dev = igea.allan(y, fs, np.array(mm) / fs, kind="modified", noise="wfm").dev
elif method == "igea_m_auto":
    dev = igea.allan(y, fs, np.array(mm) / fs, kind="modified", noise="auto").dev
elif method == "allantools_oadev":
    dev = allantools.oadev(y, fs, "freq", np.array(ms) / fs)[1]
elif method == "allantools_mdev":
    dev = allantools.mdev(y, fs, "freq", np.array(mm) / fs)[1]
else:   # the chunked numpy peers: cumulative sums, then each tau in chunks
    chunk = 1 << 20
    x = np.empty(n + 1)
    x[0] = 0.0
    np.cumsum(y - y.mean(), out=x[1:])
    dev = []
    if method == "numpy_oadev":
        for m in ms:
            s, M = 0.0, n + 1 - 2 * m
            for a in range(0, M, chunk):
                b = min(M, a + chunk)
                d = x[a + 2 * m:b + 2 * m] - 2.0 * x[a + m:b + m] + x[a:b]
                s += np.dot(d, d)
            dev.append(np.sqrt(s / M / (2.0 * m * m)))
    else:
        w = np.empty(n + 2)
        w[0] = 0.0
        np.cumsum(x, out=w[1:])
        for m in mm:
            s, M = 0.0, n + 2 - 3 * m
            for a in range(0, M, chunk):
                b = min(M, a + chunk)
                d = w[a + 3 * m:b + 3 * m] - 3 * w[a + 2 * m:b + 2 * m] + 3 * w[a + m:b + m] - w[a:b]
                s += np.dot(d, d)
            dev.append(np.sqrt(s / M / (2.0 * m ** 4)))
el = cpu() - c0
print(json.dumps({"cpu": el, "extra": hwm() - base, "dev": list(map(float, dev))}))
"""


def child(path, method, fs):
    out = subprocess.run([sys.executable, "-c", CHILD, path, method, str(fs)],
                         capture_output=True, text=True, env=ENV)
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout)


def bench_allan(path, fs, reps, have_at):
    methods = ["sum", "copy", "igea_o_wfm", "igea_o_auto", "igea_m_wfm", "igea_m_auto",
               "numpy_oadev", "numpy_mdev"]
    if have_at:
        methods += ["allantools_oadev", "allantools_mdev"]
    best, dev, extra = {}, {}, {}
    for _ in range(reps):                       # interleaved repeats
        for m in methods:
            r = child(path, m, fs)
            best[m] = min(best.get(m, 1e300), r["cpu"])
            extra[m] = max(extra.get(m, 0), r["extra"])
            dev[m] = np.array(r["dev"])
    n = int(np.load(path, mmap_mode="r").size)
    no, nm = dev["numpy_oadev"].size, dev["numpy_mdev"].size
    floor = best["sum"]
    print("Allan deviation of %d samples (%.0f MB): %d octave taus (overlapping), %d (modified);"
          " CPU s (user + sys), min of %d interleaved runs, OPENBLAS_NUM_THREADS=1"
          % (n, 8 * n / 2 ** 20, no, nm, reps))
    print("floor: one pass over the record (numpy sum) %.4f s = %.1f GB/s (a copy %.4f s);"
          % (floor, 8 * n / floor / 1e9, best["copy"]))
    print("       one pass per tau: %.4f s (overlapping, %d passes), %.4f s (modified, %d)"
          % (no * floor, no, nm * floor, nm))
    print("  %-18s %9s %14s %10s %11s" % ("method", "CPU s", "/ pass per tau", "/ one pass",
                                          "peak +MB"))
    for m in methods[2:]:
        nt = no if "_o" in m or "oadev" in m else nm
        print("  %-18s %9.4f %14.2f %10.1f %11.1f" % (m, best[m], best[m] / (nt * floor),
                                                     best[m] / floor, extra[m] / 2 ** 20))
    for k, peer, at in (("o", "numpy_oadev", "allantools_oadev"),
                        ("m", "numpy_mdev", "allantools_mdev")):
        w, a = best["igea_%s_wfm" % k], best["igea_%s_auto" % k]
        line = ("%s: chunked numpy / igea %.2f" % ("overlapping" if k == "o" else "modified",
                                                    best[peer] / w))
        if have_at:
            line += "; allantools / igea %.2f" % (best[at] / w)
        line += "; noise='auto' / given %.3f (+%.1f %%)" % (a / w, 100 * (a / w - 1))
        print(line)
    for k, peer, at in (("o", "numpy_oadev", "allantools_oadev"),
                        ("m", "numpy_mdev", "allantools_mdev")):
        d = np.max(np.abs(dev["igea_%s_wfm" % k] / dev[peer] - 1))
        line = "max relative difference igea / numpy (%s): %.1e" % (k, d)
        if have_at:
            line += ("; igea / allantools (direct sums of the differences): %.1e"
                     % np.max(np.abs(dev["igea_%s_wfm" % k] / dev[at] - 1)))
        print(line)
    print("(the chunked numpy peers difference cumulative sums of the whole record: the"
          " modified one's second sum reaches ~n^1.5 times a sample, and its short-tau"
          " differences keep only the digits above that sum's rounding)")
    print("(peak +MB: growth of the child's peak resident set over the loaded record)")


def bench_driver(path, fs, reps):
    drv = os.environ.get("IGEA_DRIVER")
    if not drv or not os.path.exists(drv):
        print("IGEA_DRIVER not set: the driver part is skipped")
        return
    runs = {"streamed": [drv, "stability", "--data", path, "--fs", str(fs), "--json", "--quiet"],
            "loaded (--gaps)": [drv, "stability", "--data", path, "--fs", str(fs), "--json",
                                "--quiet", "--gaps"]}
    best, rss, out = {}, {}, {}
    for _ in range(reps):
        for k, cmd in runs.items():
            # /usr/bin/time: maximum resident set (kB), user and system CPU s
            with tempfile.NamedTemporaryFile("r") as tf:
                p = subprocess.run(["/usr/bin/time", "-o", tf.name, "-f", "%M %U %S", *cmd],
                                   capture_output=True, text=True, env=ENV)
                if p.returncode:
                    raise SystemExit(p.stderr)
                kb, us, ss = tf.read().split()[-3:]
            best[k] = min(best.get(k, 1e300), float(us) + float(ss))
            rss[k] = max(rss.get(k, 0), int(kb))
            out[k] = json.loads(p.stdout)
    print("driver, %s (%.0f MB): maximum resident set and CPU s (min of %d)"
          % (os.path.basename(path), os.path.getsize(path) / 2 ** 20, reps))
    for k in runs:
        print("  %-16s %8.1f MB %8.3f s" % (k, rss[k] / 1024, best[k]))
    same = out["streamed"]["dev"] == out["loaded (--gaps)"]["dev"]
    print("  the same deviations bit for bit: %s" % same)


# ---- 3. the statistics shared with allantools ----

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
t0 = time.process_time()
if lib == "igea":
    k = "oadev" if kind == "gradev" else kind
    taus = [0.75 * m if kind == "theo1" else float(m) for m in ms]
    r = igea.stability(x, 1.0, taus, kind=k, data_type="phase", noise="wfm")
    dev = r.dev
else:
    taus = [0.75 * m if kind == "theo1" else float(m) for m in ms]
    out = getattr(allantools, kind)(x, 1.0, "phase", taus)
    dev = out[1]
el = time.process_time() - t0
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
                         capture_output=True, text=True, env=ENV)
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout)


def bench_allantools():
    rng = np.random.default_rng(2)
    x = np.cumsum(rng.standard_normal(10 ** 6))          # phase of white FM, tau0 = 1 s
    print("statistics shared with allantools, phase data (white FM), %d samples, CPU s"
          % x.size)
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
                  (kind, n, ms, a["time"], b["time"], b["time"] / max(a["time"], 1e-9),
                   a["extra"] / 2 ** 20, b["extra"] / 2 ** 20, d))
    print("(htotdev: igea divides by Stable32's bias factor, allantools does not; max rel d nan:\n"
          " allantools returned other taus; the record's phase alone is 7.6 MB; MB: growth of the\n"
          " child's peak resident set over it; igea's times include the EDF and intervals)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=21_600_000, help="samples (default 6 h at 1 kHz)")
    ap.add_argument("--fs", type=float, default=1000.0)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--part", choices=("allan", "driver", "allantools", "all"), default="all")
    args = ap.parse_args()
    try:
        import allantools  # noqa: F401
        have_at = True
    except ImportError:
        have_at = False
        print("allantools is not installed: its comparisons are skipped")
    if args.part in ("allantools", "all") and have_at:
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
        if args.part in ("allan", "all"):
            bench_allan(path, args.fs, args.reps, have_at)
        if args.part in ("driver", "all"):
            bench_driver(path, args.fs, args.reps)


if __name__ == "__main__":
    main()
