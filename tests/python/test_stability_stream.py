"""The record as a stream (igea_stability_stream_*, the driver's reading in
blocks) and gaps in the driver (--gaps): the streamed results equal the
whole-record library calls bit for bit, for any piece size and through a
pipe; NaN is a gap only with --gaps, refused otherwise naming
file:line:column, refused for kinds that take no gaps naming the kind; the
driver's gap results equal igea.stability on the same NaN array and report
the terms used."""
import ctypes
import json
import os
import subprocess

import numpy as np
import pytest

import igea
from igea import _capi, _lib

DRIVER = os.environ.get("IGEA_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER or not os.path.exists(DRIVER),
                                  reason="IGEA_DRIVER not built")
D = ctypes.POINTER(ctypes.c_double)
I = ctypes.POINTER(ctypes.c_int)


def run(*args, cwd=None, stdin=None):
    return subprocess.run([DRIVER, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          input=stdin)


def stream(y, fs, kind, noise, taus=None, piece=1000, data_type="freq", spacing="octave",
           block=0.0):
    lib = _lib.lib
    h = ctypes.c_void_p()
    k = _lib.choice(_capi.CHOICE_STABILITY_KIND, kind, "t", "kind")
    nz = _lib.choice(_capi.CHOICE_STABILITY_NOISE, noise, "t", "noise")
    dt = _lib.choice(_capi.CHOICE_STABILITY_DATA, data_type, "t", "data_type")
    sp = _lib.choice(_capi.CHOICE_STABILITY_TAUS, spacing, "t", "spacing")
    t = None if taus is None else np.ascontiguousarray(taus, float)
    st = lib.igea_stability_stream_create(ctypes.c_double(fs), dt, k, nz, ctypes.c_double(0.683),
                                          0 if t is None else t.size,
                                          None if t is None else t.ctypes.data_as(D), sp,
                                          ctypes.c_double(block), ctypes.byref(h))
    assert st == 0, st
    try:
        for a in range(0, y.size, piece):
            c = np.ascontiguousarray(y[a:a + piece])
            st = lib.igea_stability_stream_feed(h, c.size, c.ctypes.data_as(D))
            if st:
                return st
        K = 64
        out = [np.zeros(K) for _ in range(5)]
        al, cn = np.zeros(K, dtype=np.intc), np.zeros(K, dtype=np.intc)
        nt, blk = ctypes.c_int(), np.zeros(_capi.STABILITY_BLOCK_LEN)
        st = lib.igea_stability_stream_result(h, K, ctypes.byref(nt), *[o.ctypes.data_as(D) for o in out],
                                              al.ctypes.data_as(I), cn.ctypes.data_as(I),
                                              blk.ctypes.data_as(D))
        if st:
            return st
        # the record has ended: more samples are refused
        assert lib.igea_stability_stream_feed(h, 1, y.ctypes.data_as(D)) == _capi.EEMPTY
    finally:
        lib.igea_stability_stream_free(h)
    n = nt.value
    return [o[:n] for o in out], al[:n], cn[:n], blk


@pytest.fixture(scope="module")
def record():
    rng = np.random.default_rng(8)
    n = 5000
    return 1.0 + 0.05 * rng.standard_normal(n) + np.cumsum(rng.normal(0, 1e-3, n))


@pytest.mark.parametrize("kind", ["overlapping", "modified", "nonoverlapping"])
@pytest.mark.parametrize("noise", ["auto", "wfm"])
def test_stream_equals_allan(record, kind, noise):
    ref = igea.allan(record, 20.0, None, kind=kind, noise=noise)
    blk = igea.block_3sigma(record, 20.0, block=20.0)
    for piece in (1, 999, 1024, 5000):
        (tau, dev, lo, hi, edf), al, cn, b = stream(record, 20.0, kind, noise, piece=piece,
                                                    block=20.0)
        np.testing.assert_array_equal(tau, ref.taus)
        np.testing.assert_array_equal(dev, ref.dev)
        np.testing.assert_array_equal(lo, ref.lo)
        np.testing.assert_array_equal(edf, ref.edf)
        np.testing.assert_array_equal(cn, ref.count)
        assert b[_capi.STABILITY_BLOCK_3SIGMA] == blk.three_sigma
        assert b[_capi.STABILITY_BLOCK_ADEV] == blk.adev


@pytest.mark.parametrize("kind", ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev"])
@pytest.mark.parametrize("data_type", ["freq", "phase"])
def test_stream_equals_stability(record, kind, data_type):
    data = record if data_type == "freq" else np.cumsum(record) * 1e-9
    for spacing in ("octave", "decade"):
        ref = igea.stability(data, 20.0, spacing, kind=kind, data_type=data_type, noise="ffm")
        (tau, dev, lo, hi, edf), al, cn, b = stream(data, 20.0, kind, "ffm", piece=777,
                                                    data_type=data_type, spacing=spacing)
        np.testing.assert_array_equal(tau, ref.taus)
        np.testing.assert_array_equal(dev, ref.dev)
        np.testing.assert_array_equal(hi, ref.hi)
        np.testing.assert_array_equal(cn, ref.count)
        assert np.all(al == -1)
    # given taus; one too long for the record is refused at the end
    taus = np.array([0.05, 0.5, 10.0])
    ref = igea.stability(data, 20.0, taus, kind=kind, data_type=data_type, noise="wpm")
    (tau, dev, *_), _, _, _ = stream(data, 20.0, kind, "wpm", taus=taus, data_type=data_type)
    np.testing.assert_array_equal(dev, ref.dev)
    assert stream(data, 20.0, kind, "wpm", taus=[0.05, 1000.0],
                  data_type=data_type) == _capi.EEMPTY


def test_stream_refusals(record):
    lib = _lib.lib
    h = ctypes.c_void_p()
    mk = lambda *a: lib.igea_stability_stream_create(*a, ctypes.byref(h))
    c = ctypes.c_double
    ok = (c(10.0), 0, 0, 99, c(0.683), 0, None, 0, c(0.0))
    assert mk(*ok) == 0
    lib.igea_stability_stream_free(h)
    # phase data for a rate kind; noise auto for a Stable32 kind (its
    # identification needs the whole record); 'all' spacing
    assert mk(c(10.0), 1, 0, 99, c(0.683), 0, None, 0, c(0.0)) == -2
    assert mk(c(10.0), 0, 4, 99, c(0.683), 0, None, 0, c(0.0)) == -4
    assert mk(c(10.0), 0, 4, 0, c(0.683), 0, None, 2, c(0.0)) == -8
    assert mk(c(10.0), 0, 9, 0, c(0.683), 0, None, 0, c(0.0)) == -3     # totdev
    # a NaN or an infinity in a piece: refused, nothing of it fed
    y = record.copy()
    y[1234] = np.nan
    assert stream(y, 10.0, "overlapping", "wfm") == _capi.ENONFINITE
    y[1234] = -np.inf
    assert stream(y, 10.0, "overlapping", "wfm", piece=5000) == _capi.ENONFINITE
    assert stream(y[:1], 10.0, "overlapping", "wfm") == _capi.EEMPTY  # one sample


# ---- the driver ----------------------------------------------------------

@needs_driver
def test_driver_streams_bit_for_bit_and_through_a_pipe(tmp_path, record):
    np.save(tmp_path / "y.npy", record)
    np.savetxt(tmp_path / "y.txt", record)
    for kind, extra in (("overlapping", ()), ("modified", ("--noise", "rwfm")),
                        ("oadev", ("--noise", "wfm")), ("ohdev", ("--noise", "ffm", "--spacing", "decade"))):
        js = [json.loads(run("stability", "--data", f, "--fs", 20, "--kind", kind, *extra, "--json",
                             cwd=tmp_path).stdout) for f in ("y.npy", "y.txt")]
        piped = run("stability", "--data", "-", "--fs", 20, "--kind", kind, *extra, "--json",
                    stdin=open(tmp_path / "y.txt").read())
        assert piped.returncode == 0, piped.stderr
        js.append(json.loads(piped.stdout))
        if kind in ("overlapping", "modified"):
            noise = extra[1] if extra else "auto"
            ref = igea.allan(record, 20.0, None, kind=kind, noise=noise)
        else:
            ref = igea.stability(record, 20.0, extra[3] if len(extra) > 2 else None, kind=kind,
                                 noise=extra[1])
        for j in js:
            assert j["dev"] == list(map(float, ref.dev)) and j["edf"] == list(map(float, ref.edf))
            assert j["count"] == list(map(int, ref.count))
        assert js[0]["block"] == js[1]["block"] == js[2]["block"]


@needs_driver
def test_driver_reads_long_lags_back_from_a_npy(tmp_path):
    """A .npy record whose lags reach beyond the stream's 8 MB ring (2.2 M
    samples, octave taus to N/2): the driver reads those values back from
    the file (igea_stability_stream_source) instead of holding them; the
    results equal the whole-record library call bit for bit, for the record
    alone, a column of a C-order table and of a Fortran-order one, rate and
    phase kinds (the C tests change the file, cut it short and give a wrong
    stride: refused)."""
    rng = np.random.default_rng(41)
    n = 2_200_000
    y = 5.0 + rng.standard_normal(n) + np.cumsum(rng.standard_normal(n)) * 1e-3
    np.save(tmp_path / "y.npy", y)
    tab = np.column_stack([-y, y, 2 * y])
    np.save(tmp_path / "c.npy", tab)
    np.save(tmp_path / "f.npy", np.asfortranarray(tab))
    cases = (("overlapping", ()), ("modified", ("--noise", "wfm")), ("ohdev", ("--noise", "wfm")))
    for kind, extra in cases:
        if kind in ("overlapping", "modified"):
            ref = igea.allan(y, 100.0, None, kind=kind, noise=extra[1] if extra else "auto")
        else:
            ref = igea.stability(y, 100.0, None, kind=kind, noise=extra[1])
        assert ref.taus[-1] * 100.0 * (2 if kind == "overlapping" else 3) > 1024 * 1024
        for f, col in (("y.npy", ()), ("c.npy", ("--column", 1)), ("f.npy", ("--column", 1))):
            r = run("stability", "--data", f, *col, "--fs", 100, "--kind", kind, *extra, "--json",
                    cwd=tmp_path)
            assert r.returncode == 0, r.stderr
            j = json.loads(r.stdout)
            assert j["dev"] == list(map(float, ref.dev)), (kind, f)
            assert j["count"] == list(map(int, ref.count))


@needs_driver
def test_driver_gaps(tmp_path):
    rng = np.random.default_rng(2)
    x = np.cumsum(rng.standard_normal(3000)) * 1e-9
    txt = ["%.17g" % v for v in x]
    gaps = [10, 11, 700, 2345]
    for g in gaps:
        txt[g] = "NaN"
    (tmp_path / "g.txt").write_text("\n".join(txt) + "\n")
    # without --gaps: refused at its line and column
    r = run("stability", "--data", "g.txt", "--fs", 1, "--phase", "--kind", "oadev", cwd=tmp_path)
    assert r.returncode == 65 and "g.txt:11:1:" in r.stderr and "NaN" in r.stderr
    # another spelling or an empty field is not a gap, even with --gaps
    for bad, where in (("nan", "g2.txt:701:1:"), ("NAN", "g2.txt:701:1:"), ("-NaN", "g2.txt:701:1:")):
        t2 = list(txt)
        t2[700] = bad
        (tmp_path / "g2.txt").write_text("\n".join(t2) + "\n")
        r = run("stability", "--data", "g2.txt", "--fs", 1, "--phase", "--kind", "oadev", "--gaps",
                cwd=tmp_path)
        assert r.returncode == 65 and where in r.stderr, r.stderr
    (tmp_path / "g3.txt").write_text("1.0,2.0\n3.0,\n")
    r = run("stability", "--data", "g3.txt", "--fs", 1, "--column", 1, "--gaps", cwd=tmp_path)
    assert r.returncode == 65 and "g3.txt:2" in r.stderr, r.stderr
    # the gap-resistant kinds: the library's numbers on the same NaN array
    xn = x.copy()
    xn[gaps] = np.nan
    for kind in ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev"):
        r = run("stability", "--data", "g.txt", "--fs", 1, "--phase", "--kind", kind, "--gaps",
                "--json", cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        j = json.loads(r.stdout)
        ref = igea.stability(xn, 1.0, None, kind=kind, data_type="phase")
        assert j["dev"] == list(map(float, ref.dev)) and j["count"] == list(map(int, ref.count))
        assert j["block"] is None            # the block statistic takes no gaps
        full = igea.stability(x, 1.0, ref.taus, kind=kind, data_type="phase")
        assert np.all(ref.count <= full.count) and ref.count[0] < full.count[0]  # gaps left out
    txt_out = run("stability", "--data", "g.txt", "--fs", 1, "--phase", "--kind", "oadev",
                  "--gaps", cwd=tmp_path).stdout
    assert "gaps: 4 samples are NaN" in txt_out
    # kinds that take no gaps are refused, naming the kind
    for kind in ("totdev", "theo1", "overlapping", "mtie"):
        extra = () if kind == "overlapping" else ("--phase",)
        r = run("stability", "--data", "g.txt", "--fs", 1, *extra, "--kind", kind, "--gaps",
                cwd=tmp_path)
        assert r.returncode == 65 and "--kind %s takes no gaps" % kind in r.stderr, r.stderr
    # --gaps on a record without gaps: the usual numbers (and the block)
    np.savetxt(tmp_path / "x.txt", x)
    a = run("stability", "--data", "x.txt", "--fs", 1, "--phase", "--kind", "oadev", "--json",
            cwd=tmp_path).stdout
    b = run("stability", "--data", "x.txt", "--fs", 1, "--phase", "--kind", "oadev", "--gaps",
            "--json", cwd=tmp_path).stdout
    assert a == b
    # a .npy NaN is a gap with --gaps too
    np.save(tmp_path / "g.npy", xn)
    r = run("stability", "--data", "g.npy", "--fs", 1, "--phase", "--kind", "oadev", "--gaps",
            "--json", cwd=tmp_path)
    assert r.returncode == 0 and json.loads(r.stdout)["dev"] == json.loads(
        run("stability", "--data", "g.txt", "--fs", 1, "--phase", "--kind", "oadev", "--gaps",
            "--json", cwd=tmp_path).stdout)["dev"]
    assert run("stability", "--data", "g.npy", "--fs", 1, "--phase", "--kind", "oadev",
               cwd=tmp_path).returncode == 65
