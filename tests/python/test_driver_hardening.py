"""The driver under hostile inputs and faults: .npy shapes that overflow,
pipes and FIFOs, standard input, decimal commas, binary data passed as text,
wide stability records, malformed saved results, full disks, output files
that are links, FIFOs or devices, interrupted runs."""
import json
import os
import resource
import shutil
import signal
import stat
import struct
import subprocess
import threading
import time

import numpy as np
import pytest

DRIVER = os.environ["IGEA_DRIVER"]
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLIGHT = os.path.join(REPO, "examples", "flight")
FLIGHT_ARGS = ["--dw", "dw.txt", "--sigma", "sigma.txt", "--spec", "spec.txt"]


def run(cwd, *args, stdin=None, input=None, timeout=120):
    return subprocess.run([DRIVER, *args], cwd=cwd, capture_output=True, timeout=timeout,
                          stdin=stdin, input=input)


# A fresh, small interpreter forks the driver and reports its peak RSS: the
# child of a fork counts its parent's resident pages until exec, so the
# driver must not be forked from the (large) test process itself.
_RSS_LAUNCHER = """
import os, sys
pid = os.fork()
if pid == 0:
    os.execv(sys.argv[1], sys.argv[1:])
_, status, ru = os.wait4(pid, 0)
sys.stdout.write("%d %d" % (os.waitstatus_to_exitcode(status), ru.ru_maxrss * 1024))
"""


def run_rss(cwd, *args, stdin=None):
    """Run the driver; (returncode, stderr, peak RSS in bytes) of the driver."""
    import sys
    r = subprocess.run([sys.executable, "-S", "-c", _RSS_LAUNCHER, DRIVER, *args], cwd=cwd,
                       stdin=stdin, capture_output=True, timeout=120)
    code, rss = (int(v) for v in r.stdout.split())
    return code, r.stderr, rss


@pytest.fixture()
def flight(tmp_path):
    for f in os.listdir(FLIGHT):
        shutil.copy(os.path.join(FLIGHT, f), tmp_path / f)
    return tmp_path


def npy_header(shape, fortran=False):
    h = "{'descr': '<f8', 'fortran_order': %s, 'shape': %s, }" % (fortran, shape)
    h += " " * ((64 - (10 + len(h) + 1) % 64) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(h)) + h.encode()


def feed_fifo(path, data):
    """Write data into a FIFO from a thread (the reader may stop early)."""
    def w():
        try:
            with open(path, "wb") as f:
                f.write(data)
        except (BrokenPipeError, OSError):
            pass
    t = threading.Thread(target=w, daemon=True)
    t.start()
    return t


# ---- .npy shapes and non-seekable inputs -----------------------------------
def test_npy_shape_overflow_on_fifo(flight):
    # (2^61 + 1) x 1 doubles: rows * 8 wraps around size_t.
    os.mkfifo(flight / "big.npy")
    feed_fifo(flight / "big.npy", npy_header("(2305843009213693953, 1)") + b"\0" * 4096)
    r = run(flight, "eqerr", "--S", "big.npy", *FLIGHT_ARGS, timeout=30)
    assert r.returncode == 65, (r.returncode, r.stderr)
    assert b"big.npy" in r.stderr and b"too large" in r.stderr


def test_npy_header_larger_than_a_pipe_holds(flight):
    # 10^9 rows promised, 3 given: refused as truncated after reading what
    # is there, without sizing anything from the header.
    data = npy_header("(1000000000, 1)") + np.arange(3.0).tobytes()
    code, err, rss = run_rss(flight, "stability", "--data", "-", "--fs", "1",
                             stdin=_pipe_of(data))
    assert code == 65, err
    assert b"truncated" in err and b"1000000000" in err
    assert rss < 64 << 20


@pytest.mark.parametrize("shape", ["(1, 2147483647)", "(3, 100000000)"])
def test_npy_wide_header_on_a_pipe(flight, shape):
    # The column count of a non-seekable .npy is not trusted before the data
    # is there: refused as truncated, in little memory.
    data = npy_header(shape) + np.arange(4.0).tobytes()
    code, err, rss = run_rss(flight, "eqerr", "--S", "-", "--dw", "dw.txt", "--sigma", "0.01",
                             stdin=_pipe_of(data))
    assert code == 65, err
    assert b"truncated" in err
    assert rss < 32 << 20


def _pipe_of(data):
    rfd, wfd = os.pipe()
    def w():
        try:
            os.write(wfd, data) if len(data) < 65536 else _write_all(wfd, data)
        except OSError:
            pass
        os.close(wfd)
    threading.Thread(target=w, daemon=True).start()
    return os.fdopen(rfd, "rb")


def _write_all(fd, data):
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def eqerr_json(cwd, S, *extra, stdin=None):
    r = run(cwd, "eqerr", "--S", S, *FLIGHT_ARGS, "--json", *extra, stdin=stdin)
    assert r.returncode in (0, 1), r.stderr
    return r.stdout


@pytest.mark.parametrize("fortran", [False, True])
def test_npy_from_pipe_equals_file(flight, fortran):
    S = np.loadtxt(flight / "S.txt")
    np.save(flight / "S.npy", np.asfortranarray(S) if fortran else S)
    ref = eqerr_json(flight, "S.npy")
    with open(flight / "S.npy", "rb") as f:
        assert eqerr_json(flight, "-", stdin=f) == ref      # a file as stdin
    p = subprocess.Popen(["cat", str(flight / "S.npy")], stdout=subprocess.PIPE)
    assert eqerr_json(flight, "-", stdin=p.stdout) == ref  # cat S.npy | igea eqerr --S -
    p.wait()
    p = subprocess.Popen(["cat", str(flight / "S.npy")], stdout=subprocess.PIPE)
    assert eqerr_json(flight, "/dev/stdin", stdin=p.stdout) == ref
    p.wait()
    os.mkfifo(flight / "fifo.npy")
    feed_fifo(flight / "fifo.npy", (flight / "S.npy").read_bytes())
    assert eqerr_json(flight, "fifo.npy") == ref


@pytest.mark.parametrize("route", ["eig", "svd"])
def test_text_from_stdin_equals_file(flight, route):
    ref = eqerr_json(flight, "S.txt", "--route", route)
    p = subprocess.Popen(["cat", str(flight / "S.txt")], stdout=subprocess.PIPE)
    assert eqerr_json(flight, "-", "--route", route, stdin=p.stdout) == ref
    p.wait()
    # the other inputs from stdin too, one at a time
    with open(flight / "dw.txt", "rb") as f:
        r = run(flight, "eqerr", "--S", "S.txt", "--dw", "-", "--sigma", "sigma.txt",
                "--spec", "spec.txt", "--json", "--route", route, stdin=f)
    assert r.stdout == ref
    with open(flight / "spec.txt", "rb") as f:
        r = run(flight, "eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt",
                "--spec", "-", "--json", "--route", route, stdin=f)
    assert r.stdout == ref


def test_two_stdin_inputs_refused(flight):
    r = run(flight, "eqerr", "--S", "-", "--dw", "-", "--sigma", "0.01", input=b"")
    assert r.returncode == 64 and b"only one input" in r.stderr
    r = run(flight, "regress", "--S", "-", "--dw", "-", input=b"")
    assert r.returncode == 64 and b"only one input" in r.stderr


def test_stdin_on_other_commands(flight):
    y = np.random.default_rng(3).standard_normal(4000)
    np.savetxt(flight / "y.txt", y)
    ref = run(flight, "stability", "--data", "y.txt", "--fs", "10", "--json")
    assert ref.returncode == 0, ref.stderr
    got = run(flight, "stability", "--data", "-", "--fs", "10", "--json", input=(flight / "y.txt").read_bytes())
    assert json.loads(got.stdout)["dev"] == json.loads(ref.stdout)["dev"]
    ref = run(flight, "regress", "--method", "ls", "--S", "S.txt", "--dw", "dw.txt", "--json")
    got = run(flight, "regress", "--method", "ls", "--S", "-", "--dw", "dw.txt", "--json",
              input=(flight / "S.txt").read_bytes())
    assert ref.returncode == 0 and got.stdout == ref.stdout


# ---- decimal commas ---------------------------------------------------------
def test_decimal_comma_refused(flight):
    text = (flight / "S.txt").read_text()
    (flight / "Sc.txt").write_text(text.replace(".", ","))
    r = run(flight, "eqerr", "--S", "Sc.txt", *FLIGHT_ARGS)
    assert r.returncode == 65, (r.returncode, r.stdout[-300:])
    assert b"decimal comma" in r.stderr
    # file:line:column of the first comma between digits
    lines = (flight / "Sc.txt").read_text().split("\n")
    ln = next(i for i, l in enumerate(lines) if not l.startswith("#") and "," in l)
    col = lines[ln].index(",") + 1
    assert ("Sc.txt:%d:%d:" % (ln + 1, col)).encode() in r.stderr, r.stderr
    assert r.stdout == b""


def test_genuine_csv_accepted(flight):
    S = np.loadtxt(flight / "S.txt")
    np.savetxt(flight / "S.csv", S, delimiter=",", fmt="%.17g")    # 1.5,2.5,3
    np.savetxt(flight / "S2.csv", S, delimiter=", ", fmt="%.17g")  # 1.5, 2.5, 3
    np.savetxt(flight / "S.sp", S, fmt="%.17g")
    ref = eqerr_json(flight, "S.sp")
    assert eqerr_json(flight, "S.csv") == ref
    assert eqerr_json(flight, "S2.csv") == ref
    ints = np.arange(1, 13, dtype=float).reshape(4, 3)
    (flight / "i.csv").write_text("\n".join(",".join("%d" % v for v in row) for row in ints))
    r = run(flight, "stability", "--data", "i.csv", "--fs", "1", "--column", "1", "--json")
    assert r.returncode == 0, r.stderr


def test_column_mismatch_blames_S(flight):
    S = np.loadtxt(flight / "S.txt")
    np.savetxt(flight / "Swide.txt", np.hstack([S, S[:, :1]]))
    r = run(flight, "eqerr", "--S", "Swide.txt", *FLIGHT_ARGS)
    assert r.returncode == 65
    assert r.stderr.startswith(b"igea: Swide.txt: %d columns" % (S.shape[1] + 1)), r.stderr
    assert b"spec.txt" in r.stderr


# ---- binary data passed as text ---------------------------------------------
@pytest.mark.parametrize("kind", ["no_newline", "nul"])
def test_binary_as_text_refused_early(tmp_path, kind):
    big = tmp_path / "big.txt"
    with open(big, "wb") as f:
        if kind == "nul":
            f.write(b"1\n2\n")  # a good start, then 50 MB of NUL bytes
        chunk = (b"1" * (1 << 20)) if kind == "no_newline" else b"\0" * (1 << 20)
        for _ in range(50):
            f.write(chunk)
    t0 = time.time()
    code, err, rss = run_rss(tmp_path, "stability", "--data", "big.txt", "--fs", "1")
    assert code == 65, err
    assert b"big.txt:" in err
    assert (b"line longer than" in err) if kind == "no_newline" else (b"NUL byte" in err)
    assert rss < 32 << 20, rss
    assert time.time() - t0 < 20


# ---- stability of a wide file -----------------------------------------------
def test_stability_wide_file_needs_column(tmp_path):
    rng = np.random.default_rng(8)
    rate = rng.standard_normal(3000)
    t = np.arange(3000) / 10.0
    np.savetxt(tmp_path / "tr.txt", np.column_stack([t, rate]), fmt="%.17g")
    np.savetxt(tmp_path / "r.txt", rate, fmt="%.17g")
    r = run(tmp_path, "stability", "--data", "tr.txt", "--fs", "10")
    assert r.returncode == 64
    assert b"tr.txt" in r.stderr and b"2 columns" in r.stderr and b"--column" in r.stderr
    a = run(tmp_path, "stability", "--data", "tr.txt", "--fs", "10", "--column", "1", "--json")
    b = run(tmp_path, "stability", "--data", "r.txt", "--fs", "10", "--json")
    assert a.returncode == 0 and b.returncode == 0
    ja, jb = json.loads(a.stdout), json.loads(b.stdout)
    assert ja["dev"] == jb["dev"]
    # the overlapping Allan deviation at tau = 1 sample, computed here
    d = np.diff(rate)
    assert ja["taus"][0] == pytest.approx(0.1)
    assert ja["dev"][0] == pytest.approx(np.sqrt(0.5 * np.mean(d * d)), rel=1e-12)
    h = run(tmp_path, "stability", "--help")
    assert b"--column" in h.stdout


# ---- igea test: counts in saved results -------------------------------------
@pytest.mark.parametrize("field,value", [("n_reject", "0.9"), ("dof", "1e10"), ("chi2", "-2"),
                                         ("dof", "-3"), ("n_reject", "2.5e9")])
def test_saved_result_counts_checked(flight, field, value):
    doc = eqerr_json(flight, "S.txt").decode()
    lines = [("  \"%s\": %s," % (field, value)) if l.startswith("  \"%s\":" % field) else l
             for l in doc.split("\n")]
    (flight / "bad.json").write_text("\n".join(lines))
    r = run(flight, "test", "--results", "bad.json")
    assert r.returncode == 65, (r.returncode, r.stdout, r.stderr)
    assert b"bad.json" in r.stderr and field.encode() in r.stderr


def test_saved_result_binary_refused_early(tmp_path):
    code, err, rss = run_rss(tmp_path, "test", "--results", "/dev/zero")
    assert code == 65 and b"/dev/zero" in err and b"NUL" in err
    assert rss < 32 << 20


# ---- standard output on a full disk -----------------------------------------
@pytest.fixture(scope="module")
def traj(tmp_path_factory):
    d = tmp_path_factory.mktemp("traj")
    r = run(d, "simulate", "--seed", "2", "--duration", "30", "--save-traj", "--dir", str(d))
    assert r.returncode == 0, r.stderr
    return d


@pytest.mark.parametrize("args", [
    ["envfun", "--traj", "traj.txt", "--terms", "default"],
    ["envfun", "--traj", "traj.txt", "--terms", "default", "--json"],
    ["envfun", "--list"],
    ["simulate", "--duration", "30", "--json", "--dir", "."],
    ["montecarlo", "--flights", "20", "--duration", "30"],
    ["montecarlo", "--flights", "20", "--duration", "30", "--json"],
    ["version"],
    ["--help"],
    ["eqerr", "--help"],
    ["eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--spec", "spec.txt"],
    ["stability", "--data", "dw.txt", "--fs", "1", "--block", "2"],
])
def test_stdout_full_is_an_error(traj, args):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    with open("/dev/full", "wb") as full:
        r = subprocess.run([DRIVER, *args], cwd=traj, stdout=full, stderr=subprocess.PIPE,
                           timeout=120)
    assert r.returncode == 74, (args, r.returncode, r.stderr)
    assert r.stderr.count(b"\n") == 1 and b"standard output" in r.stderr


def test_lost_summary_keeps_old_files(traj, tmp_path):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt", "X.txt", "Senv.txt"):
        (tmp_path / f).write_text("old\n")
    with open("/dev/full", "wb") as full:
        a = subprocess.run([DRIVER, "simulate", "--duration", "30", "--json", "--dir", "."],
                           cwd=tmp_path, stdout=full, stderr=subprocess.PIPE, timeout=120)
        b = subprocess.run([DRIVER, "envfun", "--traj", str(traj / "traj.txt"), "--terms", "default",
                            "--json", "--out", "Senv.txt"], cwd=tmp_path, stdout=full,
                           stderr=subprocess.PIPE, timeout=120)
    assert a.returncode == 74 and b.returncode == 74, (a.stderr, b.stderr)
    for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt", "X.txt", "Senv.txt"):
        assert (tmp_path / f).read_text() == "old\n", f
    assert not [f for f in os.listdir(tmp_path) if ".tmp." in f]


# ---- output files -------------------------------------------------------------
def write_out(cwd, out):
    return run(cwd, "eqerr", "--S", "S.txt", *FLIGHT_ARGS, "--json", "--out", out)


def test_out_keeps_mode_and_umask(flight):
    (flight / "r.json").write_text("old")
    os.chmod(flight / "r.json", 0o600)
    assert write_out(flight, "r.json").returncode == 0
    assert stat.S_IMODE(os.stat(flight / "r.json").st_mode) == 0o600
    assert json.loads((flight / "r.json").read_text())["n_terms"] == 18
    old = os.umask(0o077)
    try:
        assert write_out(flight, "new.json").returncode == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(flight / "new.json").st_mode) == 0o600
    old = os.umask(0o022)
    try:
        assert write_out(flight, "new2.json").returncode == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(flight / "new2.json").st_mode) == 0o644


def test_out_follows_symlink(flight):
    (flight / "sub").mkdir()
    (flight / "sub" / "target.json").write_text("old")
    os.chmod(flight / "sub" / "target.json", 0o640)
    os.symlink("sub/target.json", flight / "link.json")
    assert write_out(flight, "link.json").returncode == 0
    assert os.path.islink(flight / "link.json")
    assert json.loads((flight / "sub" / "target.json").read_text())["n_terms"] == 18
    assert stat.S_IMODE(os.stat(flight / "sub" / "target.json").st_mode) == 0o640
    assert not [f for f in os.listdir(flight / "sub") if ".tmp." in f]
    assert not [f for f in os.listdir(flight) if ".tmp." in f]
    # a dangling link: its target is created
    os.symlink("sub/fresh.json", flight / "dangling.json")
    assert write_out(flight, "dangling.json").returncode == 0
    assert os.path.islink(flight / "dangling.json")
    assert json.loads((flight / "sub" / "fresh.json").read_text())["n_terms"] == 18


def test_out_fifo_written_in_place(flight):
    os.mkfifo(flight / "pipe.json")
    got = []
    def reader():
        with open(flight / "pipe.json", "rb") as f:
            got.append(f.read())
    t = threading.Thread(target=reader, daemon=True)
    t.start()
    r = write_out(flight, "pipe.json")
    t.join(30)
    assert r.returncode == 0, r.stderr
    assert stat.S_ISFIFO(os.lstat(flight / "pipe.json").st_mode)
    assert json.loads(got[0])["n_terms"] == 18
    assert not [f for f in os.listdir(flight) if ".tmp." in f]


def test_out_dev_stdout_is_the_pipe(flight):
    # a private link like /dev/stdout, so the system's own is never at stake
    os.symlink("/proc/self/fd/1", flight / "stdout")
    r = write_out(flight, "stdout")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["n_terms"] == 18
    assert os.path.islink(flight / "stdout")
    assert not [f for f in os.listdir(flight) if ".tmp." in f]


def _restore_dev_null():
    st = os.lstat("/dev/null")
    if not stat.S_ISCHR(st.st_mode) and os.geteuid() == 0:
        os.unlink("/dev/null")
        os.mknod("/dev/null", 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        os.chmod("/dev/null", 0o666)


def test_out_device_stays_a_device(flight):
    # A private node first (as root: a copy of /dev/null in the test's own
    # directory); the real /dev/null only once that one came through intact.
    if os.geteuid() == 0:
        node = flight / "null"
        try:
            os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
            open(node, "wb").close()
        except OSError:
            pytest.skip("cannot use a device node here")
        r = write_out(flight, str(node))
        assert r.returncode == 0, r.stderr
        assert stat.S_ISCHR(os.lstat(node).st_mode), "the device node was replaced"
        assert not [f for f in os.listdir(flight) if ".tmp." in f]
    before = os.stat("/dev/null")
    assert stat.S_ISCHR(before.st_mode)
    try:
        r = write_out(flight, "/dev/null")
    finally:
        _restore_dev_null()
    assert r.returncode == 0, r.stderr
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev
    assert stat.S_IMODE(after.st_mode) == stat.S_IMODE(before.st_mode)


def full_device(d):
    """A device that refuses every write (ENOSPC) to use as an output file:
    as root a private copy of /dev/full in d, so that a driver that replaced
    its --out target could never replace the system's /dev/full."""
    if os.geteuid() != 0:
        return "/dev/full"
    node = os.path.join(str(d), "full")
    try:
        os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 7))
        with open(node, "wb", buffering=0) as f:
            f.write(b"x")
    except OSError as e:
        if e.errno == 28:   # ENOSPC: the node works
            return node
    pytest.skip("cannot use a device node here")


def test_eqerr_report_and_residuals_together(flight):
    full = full_device(flight)
    (flight / "res.txt").write_text("old\n")
    r = run(flight, "eqerr", "--S", "S.txt", *FLIGHT_ARGS, "--residuals", "res.txt",
            "--out", full)
    assert stat.S_ISCHR(os.lstat(full).st_mode)
    assert r.returncode == 74, r.stderr
    assert r.stderr.count(b"\n") == 1 and b"full" in r.stderr
    assert (flight / "res.txt").read_text() == "old\n"
    assert not [f for f in os.listdir(flight) if ".tmp." in f]


def test_simulate_dir_all_or_nothing(tmp_path):
    r = run(tmp_path, "simulate", "--seed", "1", "--duration", "30", "--dir", ".")
    assert r.returncode == 0, r.stderr
    old = {f: (tmp_path / f).read_bytes() for f in ("S.txt", "dw.txt", "sigma.txt", "spec.txt")}
    (tmp_path / "X.txt").unlink()
    (tmp_path / "X.txt").mkdir()  # the last file cannot be written
    r = run(tmp_path, "simulate", "--seed", "2", "--duration", "30", "--dir", ".")
    assert r.returncode == 74, r.stderr
    assert r.stderr.count(b"\n") == 1 and b"X.txt" in r.stderr
    for f, data in old.items():
        assert (tmp_path / f).read_bytes() == data, f
    assert not [f for f in os.listdir(tmp_path) if ".tmp." in f]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_signal_removes_temporaries(tmp_path, sig):
    (tmp_path / "mc.txt").write_text("old table\n")
    # the signal's default disposition in the child: a test run started in
    # the background of a shell without job control inherits SIGINT ignored,
    # which the driver rightly keeps (as it keeps nohup's SIGHUP)
    p = subprocess.Popen([DRIVER, "montecarlo", "--flights", "1000000", "--threads", "1",
                          "--out", "mc.txt"], cwd=tmp_path, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL,
                         preexec_fn=lambda: signal.signal(sig, signal.SIG_DFL))
    try:
        for _ in range(500):
            if [f for f in os.listdir(tmp_path) if ".tmp." in f]:
                break
            time.sleep(0.01)
        assert [f for f in os.listdir(tmp_path) if ".tmp." in f], "no temporary seen"
        p.send_signal(sig)
        p.wait(30)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert p.returncode == -sig
    assert not [f for f in os.listdir(tmp_path) if ".tmp." in f]
    assert (tmp_path / "mc.txt").read_text() == "old table\n"
