"""Progress on stderr for the long jobs: igea montecarlo, igea stability
and the streamed igea eqerr
(--progress: a line per 10 %; in place on a terminal; --quiet: nothing) and
igea.montecarlo(progress=...). The work is split into chunks the library
supports; the results must be the same, bit for bit, with and without the
progress shown, and the same as one library call over everything.

Runtime: about 10 s on an idle core (200-flight runs, a 20000-sample record)."""
import ctypes
import json
import os
import pty
import re
import subprocess
import sys

import numpy as np
import pytest

import igea
from igea import _capi, _lib

DRIVER = os.environ.get("IGEA_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER),
                                  reason="IGEA_DRIVER not built")
LINE = re.compile(r"^igea (\w+): +(\d+) % \((\d+) of (\d+) ([a-z ]+)\), [0-9.]+ s elapsed, "
                  r"(ETA [0-9.]+ s|done)$")


def run(*args, stderr=subprocess.PIPE, cwd=None):
    return subprocess.run([DRIVER, *map(str, args)], stdout=subprocess.PIPE, stderr=stderr,
                          text=True, cwd=cwd)


def batch_lines(err, cmd, total, unit):
    """The --progress lines: one per 10 % passed, ending at 100 %."""
    lines = err.splitlines()
    got = [LINE.match(x) for x in lines]
    assert all(got), lines
    assert {m.group(1) for m in got} == {cmd} and {m.group(5) for m in got} == {unit}
    pct = [int(m.group(2)) for m in got]
    done = [int(m.group(3)) for m in got]
    assert pct == sorted(set(pct)) and pct[-1] == 100 and done[-1] == total
    assert [p // 10 for p in pct] == sorted(set(p // 10 for p in pct))  # one per decile
    for p, d in zip(pct, done):   # the percentage is of the units done
        assert p == (100 if d == total else 100 * d // total)
    assert got[-1].group(6) == "done" and all(m.group(6) != "done" for m in got[:-1])
    return pct


MC = ("montecarlo", "--flights", 200, "--seed", 5, "--sigma-w", 1.2, "--json")


@needs_driver
def test_montecarlo_progress_lines_and_same_result(tmp_path):
    quiet = run(*MC, "--quiet", "--out", tmp_path / "q.txt")
    plain = run(*MC, "--out", tmp_path / "p.txt")
    shown = run(*MC, "--progress", "--out", tmp_path / "s.txt")
    assert quiet.returncode == plain.returncode == shown.returncode == 0
    assert quiet.stdout == plain.stdout == shown.stdout
    assert (tmp_path / "q.txt").read_bytes() == (tmp_path / "s.txt").read_bytes()
    assert quiet.stderr == "" and plain.stderr == ""   # stderr is a pipe here: no progress
    # 200 flights in chunks of 20: exactly the ten deciles
    assert batch_lines(shown.stderr, "montecarlo", 200, "flights") == list(range(10, 101, 10))


@needs_driver
def test_montecarlo_means_are_the_flight_by_flight_ones(tmp_path):
    """The chunks' means are rebuilt as one library call computes them:
    the sum over the testable flights, in flight order (igea_sim_montecarlo's
    loop), divided by their number; checked against the per-flight table."""
    r = run(*MC, "--progress", "--out", tmp_path / "t.txt")
    js = json.loads(r.stdout)
    t = np.loadtxt(tmp_path / "t.txt")
    scale, dof = t[:, 4], t[:, 2]
    ok = np.isfinite(scale)
    s = 0.0
    for v in scale[ok]:
        s += float(v)
    assert js["mean_scale"] == s / ok.sum()
    assert js["mean_tested"] == dof[ok].sum() / ok.sum()
    assert js["not_testable"]["count"] == int((~ok).sum())


@needs_driver
def test_progress_on_a_terminal_is_updated_in_place():
    master, slave = pty.openpty()
    try:
        r = subprocess.run([DRIVER, *map(str, MC)], stdout=subprocess.PIPE, stderr=slave,
                           text=True)
        os.close(slave)
        slave = None
        out = b""
        while True:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                break
            if not chunk:
                break
            out += chunk
    finally:
        os.close(master)
        if slave is not None:
            os.close(slave)
    text = out.decode()
    assert r.returncode == 0 and r.stdout == run(*MC, "--quiet").stdout
    assert "\r" in text and text.rstrip().endswith("done")
    assert text.count("\n") == 1 and "100 % (200 of 200 flights)" in text


@needs_driver
def test_streamed_eqerr_progress_and_same_result(tmp_path):
    """Pass 1 (the rows are not known yet): the count read; pass 2: the
    percentage of the rows, a line per 10 % passed. Three row blocks."""
    rng = np.random.default_rng(2)
    m, N = 3 * 12000, 30
    S = rng.standard_normal((m, N))
    np.save(tmp_path / "S.npy", S)
    np.save(tmp_path / "dw.npy", S @ (0.01 * rng.standard_normal(N)) +
            0.01 * rng.standard_normal(m))
    args = ("eqerr", "--S", "S.npy", "--dw", "dw.npy", "--sigma", 0.01, "--json")
    a = run(*args, "--quiet", "--residuals", "a.txt", cwd=tmp_path)
    b = run(*args, "--progress", "--residuals", "b.txt", cwd=tmp_path)
    c = run(*args, "--residuals", "c.txt", cwd=tmp_path)
    assert a.returncode == b.returncode == c.returncode and a.returncode in (0, 1), b.stderr
    assert a.stdout == b.stdout == c.stdout and a.stderr == c.stderr == ""
    assert (tmp_path / "a.txt").read_bytes() == (tmp_path / "b.txt").read_bytes()
    lines = b.stderr.splitlines()
    first = [x for x in lines if "pass 1 of 2" in x]
    counts = [int(re.match(r"^igea eqerr: (\d+) rows read \(pass 1 of 2\), [0-9.]+ s elapsed$",
                           x).group(1)) for x in first]
    assert counts and counts[0] > 0 and all(b >= 2 * a for a, b in zip(counts, counts[1:]))
    second = "\n".join(x for x in lines if "pass 1 of 2" not in x)
    second = second.replace("rows, pass 2 of 2", "rows")
    pct = batch_lines(second, "eqerr", m, "rows")
    assert len(pct) >= 2   # more than one block


@needs_driver
def test_progress_and_quiet_exclude_each_other():
    r = run(*MC, "--progress", "--quiet")
    assert r.returncode == 64 and "--progress and --quiet" in r.stderr and r.stdout == ""
    flight = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))), "examples", "flight")
    eq = ("eqerr", "--S", "S.txt", "--dw", "dw.txt", "--sigma", "sigma.txt", "--progress",
          "--quiet")
    for extra in ((), ("--robust",)):   # streamed, and the whole-flight noise route
        r = run(*eq, *extra, cwd=flight)
        assert r.returncode == 64 and "--progress and --quiet" in r.stderr, (extra, r.stderr)


@needs_driver
@pytest.mark.parametrize("cmd", ["montecarlo", "stability", "eqerr"])
def test_options_in_help_man_page_and_completion(cmd):
    h = run(cmd, "--help").stdout
    assert re.search(r"^  --progress +progress and ETA", h, re.M)
    assert re.search(r"^  --quiet +no progress", h, re.M)
    share = os.path.join(os.path.dirname(os.path.dirname(DRIVER)), "share")
    if not os.path.exists(os.path.join(share, "igea.1")):
        pytest.skip("the man page is not built")
    page = open(os.path.join(share, "igea.1")).read()
    sec = page[page.index(".SS %s\n" % cmd):]
    sec = sec[:sec.index(".SS ", 4)]
    assert "\\-\\-progress" in sec and "\\-\\-quiet" in sec
    comp = [x for x in open(os.path.join(share, "igea.bash"))
            if {"stability": "--fs", "montecarlo": "--flights", "eqerr": "--lags"}[cmd] in x]
    assert any("--progress --quiet" in x for x in comp)


KINDS = ["overlapping", "modified", "nonoverlapping", "adev", "oadev", "mdev", "tdev", "hdev",
         "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev", "theo1", "mtie", "tierms"]


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    d = tmp_path_factory.mktemp("stab")
    rng = np.random.default_rng(11)
    y = rng.normal(size=20000) + 1e-2 * np.cumsum(rng.normal(size=20000))
    np.savetxt(d / "y.txt", y)
    # averaging times out of order, some with fewer than 32 tau-averages
    # (the rate-data kinds carry the noise type found before them there)
    np.savetxt(d / "taus.txt", [0.1, 80.0, 3.2, 120.0, 160.0, 1.0, 70.0, 100.0])
    return d, y


@needs_driver
@pytest.mark.parametrize("kind", KINDS)
def test_stability_same_numbers_with_progress(record, kind):
    d, _ = record
    args = ("stability", "--data", "y.txt", "--fs", 10, "--kind", kind, "--json")
    a = run(*args, "--quiet", cwd=d)
    b = run(*args, "--progress", cwd=d)
    assert a.returncode == b.returncode == 0, b.stderr
    assert a.stdout == b.stdout and a.stderr == ""
    n = len(json.loads(a.stdout)["taus"])
    if kind in ("overlapping", "modified", "nonoverlapping"):
        # the record streamed (the samples read so far, a line each time the
        # count has doubled)
        counts = [int(re.match(r"^igea stability: (\d+) samples read, [0-9.]+ s elapsed$",
                               x).group(1)) for x in b.stderr.splitlines()]
        assert counts and counts[0] > 0 and counts[-1] <= 20000
        assert all(c2 >= 2 * c1 for c1, c2 in zip(counts, counts[1:]))
    else:
        batch_lines(b.stderr, "stability", n, "averaging times")
    if kind in ("overlapping", "modified", "nonoverlapping"):
        t = ("--taus", "taus.txt")
        a = run(*args, *t, "--quiet", cwd=d)
        b = run(*args, *t, "--progress", cwd=d)
        assert a.returncode == b.returncode == 0 and a.stdout == b.stdout, b.stderr


def test_stability_rate_kinds_equal_the_python_call(record):
    """The driver's per-tau groups give igea.allan's numbers (one library
    call over all taus), bit for bit, with the noise type identified."""
    d, y = record
    if not DRIVER or not os.path.exists(DRIVER):
        pytest.skip("IGEA_DRIVER not built")
    taus = np.loadtxt(d / "taus.txt")
    b = json.loads(run("stability", "--data", "y.txt", "--fs", 10, "--taus", "taus.txt",
                       "--json", "--progress", cwd=d).stdout)
    r = igea.allan(y, 10.0, taus=taus)
    assert b["dev"] == list(map(float, r.dev))
    assert b["edf"] == list(map(float, r.edf))


# ---- Python ---------------------------------------------------------------

@pytest.fixture(scope="module")
def model():
    rng = np.random.default_rng(3)
    return rng.normal(size=(60, 6)), np.full(60, 0.5)


def as_plain(r):
    return json.loads(json.dumps(r.to_dict(), allow_nan=True).replace("NaN", "null"))


def one_call(S, sigma, flights, seed, sigma_w):
    """igea_sim_montecarlo called once over all flights (the reference)."""
    from igea.sim import _Model
    m, N = S.shape
    S = np.asfortranarray(S)
    eq = np.zeros(_capi.EQERR_OPT_LEN)
    _lib.lib.igea_eqerr_defaults(_lib.dptr(eq))
    eq[_capi.EQERR_OPT_OVERALL_SIZE] = 1
    counts, rates = np.zeros(_capi.SIM_MC_LEN), np.zeros(_capi.SIM_MC_RATES_LEN)
    ct, cr = np.zeros(N, dtype=np.intc), np.zeros(N, dtype=np.intc)
    table = np.zeros((flights, _capi.SIM_MC_TABLE_COLS), order="F")
    with _Model("t", "igea_sim_model_create", m, N, _lib.dptr(S), m) as h:
        h.set("sigma", _lib.dptr(sigma), 1, 0.0)
        h.set("spec", None)
        h.noise("mt19937", sigma_w=sigma_w)
        h.set("truth", _lib.dptr(np.zeros(N)), _lib.iptr(np.zeros(N, dtype=np.intc)))
        assert _lib.lib.igea_sim_montecarlo(h.h, _lib.dptr(eq), seed, 0, flights, 1,
                                            _lib.dptr(counts), _lib.dptr(rates), _lib.iptr(ct),
                                            _lib.iptr(cr), _lib.dptr(table), flights) == 0
    return counts, rates, ct, cr, table


def test_python_chunks_equal_one_library_call(model):
    S, sigma = model
    counts, rates, ct, cr, table = one_call(S, sigma, 230, 9, 1.4)
    r = igea.montecarlo(S, sigma, 230, seed=9, sigma_w=1.4, threads=1, progress=True)
    c = lambda k: counts[getattr(_capi, "SIM_MC_" + k)]
    assert (r.flights, r.failed, r.chi2_reject, r.any_reject, r.not_testable) == \
        tuple(int(c(k)) for k in ("FLIGHTS", "FAILED", "CHI2_REJECT", "ANY_REJECT",
                                  "NOT_TESTABLE"))
    assert r.mean_scale == c("MEAN_SCALE") and r.mean_tested == c("MEAN_TESTED")
    assert r.mean_size == pytest.approx(c("MEAN_SIZE"), rel=1e-13)
    np.testing.assert_array_equal(r.chi2, table[:, _capi.SIM_MC_TABLE_CHI2])
    np.testing.assert_array_equal(r.comp_tested, ct)
    np.testing.assert_array_equal(r.comp_reject, cr)
    assert r.rates["failed"] == rates[0] and r.ci99["failed"] == (rates[1], rates[2])


def test_python_progress_lines_and_same_result(model, capsys, monkeypatch):
    S, sigma = model
    monkeypatch.setitem(sys.modules, "tqdm", None)   # tqdm hidden: the plain lines
    a = igea.montecarlo(S, sigma, 200, seed=2, pool=4)
    assert capsys.readouterr().err == ""
    b = igea.montecarlo(S, sigma, 200, seed=2, pool=4, progress=True)
    err = capsys.readouterr().err
    assert as_plain(a) == as_plain(b)
    np.testing.assert_array_equal(a.scale, b.scale)
    lines = [re.sub(r"^igea\.montecarlo", "igea montecarlo", x) for x in err.splitlines()]
    assert batch_lines("\n".join(lines), "montecarlo", 200, "flights") == \
        list(range(10, 101, 10))


def test_python_progress_function_and_tqdm(model, monkeypatch):
    S, sigma = model
    seen = []
    igea.montecarlo(S, sigma, 37, seed=1, progress=lambda done, total: seen.append((done, total)))
    assert seen == [(d, 37) for d in (4, 8, 12, 16, 20, 24, 28, 32, 36, 37)]

    class Bar:  # the part of tqdm.tqdm used
        made = []

        def __init__(self, total, unit, desc):
            self.total, self.n, self.closed = total, 0, False
            Bar.made.append(self)

        def update(self, k):
            self.n += k

        def close(self):
            self.closed = True

    fake = type(sys)("tqdm")
    fake.tqdm = Bar
    monkeypatch.setitem(sys.modules, "tqdm", fake)
    igea.montecarlo(S, sigma, 37, seed=1, progress=True)
    assert len(Bar.made) == 1 and Bar.made[0].n == 37 and Bar.made[0].closed
    with pytest.raises(TypeError, match="progress"):
        igea.montecarlo(S, sigma, 5, progress="yes")
