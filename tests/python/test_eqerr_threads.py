"""igea_eqerr_run's normal equations on several threads
(IGEA_EQERR_OPT_THREADS, igea.eqerr(threads=)): rows in segments of 8192,
each segment's sums its own, added in segment order. So the result is the
same bit for bit for every thread count >= 2, and equals the one-thread
sums to rounding: the eigenvalues agree with numpy's eigvalsh of the
weighted normal matrix (written here) to 1e-12 of the largest."""
import numpy as np
import pytest

import igea
from igea import _capi, _lib

lib = _lib.lib


def flight(m=70000, N=12, seed=3, sigma_rows=False):
    rng = np.random.default_rng(seed)
    S = np.asfortranarray(rng.standard_normal((m, N)) * np.logspace(-1, 1, N))
    spec = np.linspace(0.5, 2.0, N)
    sigma = np.full(m, 0.01) if not sigma_rows else 0.01 * (1 + 0.5 * rng.random(m))
    dw = S @ (spec * rng.standard_normal(N)) * 1e-3 + sigma * rng.standard_normal(m)
    return S, dw, sigma, spec


@pytest.mark.parametrize("sigma_rows", [False, True])
def test_thread_counts_give_one_result(sigma_rows):
    S, dw, sigma, spec = flight(sigma_rows=sigma_rows)  # 9 segments
    ref = igea.eqerr(S, dw, sigma, spec, threads=2)
    for t in (3, 4, 7):
        got = igea.eqerr(S, dw, sigma, spec, threads=t)
        for k in ("chi2", "scale", "eigenvalues", "equiv_err", "z", "residual"):
            np.testing.assert_array_equal(getattr(ref, k), getattr(got, k), err_msg=k)


@pytest.mark.parametrize("sigma_rows", [False, True])
def test_equal_to_one_thread_to_rounding(sigma_rows):
    S, dw, sigma, spec = flight(sigma_rows=sigma_rows)
    St = S * spec / sigma[:, None]
    ref = np.sort(np.linalg.eigvalsh(St.T @ St))[::-1]
    one = igea.eqerr(S, dw, sigma, spec)
    two = igea.eqerr(S, dw, sigma, spec, threads=2)
    for r in (one, two):
        np.testing.assert_allclose(r.eigenvalues, ref, rtol=0, atol=1e-12 * ref[0])
    assert two.n_test == one.n_test and two.passed == one.passed
    assert two.chi2 == pytest.approx(one.chi2, rel=1e-9)
    assert two.scale == pytest.approx(one.scale, rel=1e-9)


def test_threads_slot_checked_and_named():
    opts = np.zeros(_capi.EQERR_OPT_LEN)
    lib.igea_eqerr_defaults(_lib.dptr(opts))
    assert lib.igea_eqerr_check_opts(_lib.dptr(opts)) == 0
    for bad in (-1.0, 1.5, _capi.EQERR_THREADS_MAX + 1.0):
        opts[_capi.EQERR_OPT_THREADS] = bad
        assert lib.igea_eqerr_check_opts(_lib.dptr(opts)) == 1 + _capi.EQERR_OPT_THREADS
    assert lib.igea_opt_name(_capi.MODULE_EQERR, _capi.EQERR_OPT_THREADS).decode() == "threads"
    S, dw, sigma, spec = flight(m=300)
    with pytest.raises(igea.IgeaError, match="threads"):
        igea.eqerr(S, dw, sigma, spec, threads=-2)


def test_a_nan_in_a_late_segment():
    S, dw, sigma, spec = flight()
    S[65000, 3] = np.nan
    with pytest.raises(igea.IgeaError) as e:
        igea.eqerr(S, dw, sigma, spec, threads=2)
    assert e.value.code == _capi.ENONFINITE


def test_driver_threads(tmp_path):
    """igea eqerr --threads T: the same JSON for T = 2 and 3 (the driver's
    blocks of four segments whatever T), equal to --threads 1 to rounding; a
    bad T is refused naming the option."""
    import json
    import os
    import subprocess
    S, dw, sigma, spec = flight(m=90000)
    np.save(tmp_path / "S.npy", np.ascontiguousarray(S))
    np.save(tmp_path / "dw.npy", dw)
    drv = os.environ["IGEA_DRIVER"]

    def run(*extra):
        p = subprocess.run([drv, "eqerr", "--S", "S.npy", "--dw", "dw.npy", "--sigma", "0.01",
                            "--json", *extra], cwd=tmp_path, capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    rc1, out1, _ = run()
    rc2, out2, _ = run("--threads", "2")
    rc3, out3, _ = run("--threads", "3")
    assert rc1 == rc2 == rc3 and rc1 in (0, 1)
    d1, d2, d3 = json.loads(out1), json.loads(out2), json.loads(out3)
    assert d2 == d3
    assert d2["chi2"] == pytest.approx(d1["chi2"], rel=1e-9)
    assert d2["n_test"] == d1["n_test"] and d2["passed"] == d1["passed"]
    rc, _, err = run("--threads", "-1")
    assert rc == 64 and "--threads" in err


@pytest.mark.parametrize("sigma_rows", [False, True])
def test_residual_pass_on_threads(sigma_rows):
    """The residual pass runs in the same segments on the same threads: the
    residuals, the per-axis RMS and chi2 are the same bits for T = 2, 3, 4;
    they equal one thread's to rounding; the RMS is that of the returned
    residuals per axis (rows i with i mod 3 = a; 8192 mod 3 = 2, so the
    axes rotate across the segment boundaries); and the residuals are dw
    minus a fit in the column space of S (numpy's lstsq of the residuals on
    S leaves them, to rounding, only in the untested directions)."""
    S, dw, sigma, spec = flight(m=70001, sigma_rows=sigma_rows)  # 9 segments
    runs = {t: igea.eqerr(S, dw, sigma, spec, threads=t) for t in (1, 2, 3, 4)}
    for t in (3, 4):
        for k in ("residual", "rms", "chi2"):
            np.testing.assert_array_equal(getattr(runs[2], k), getattr(runs[t], k), err_msg=k)
    one, two = runs[1], runs[2]
    scale = np.max(np.abs(dw))
    np.testing.assert_allclose(two.residual, one.residual, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(two.rms, one.rms, rtol=1e-12)
    for r in (one, two):
        want = [np.sqrt(np.mean(r.residual[a::3] ** 2)) for a in range(3)]
        np.testing.assert_allclose(r.rms, want, rtol=1e-12)
        fit = dw - r.residual
        coef, *_ = np.linalg.lstsq(S, fit, rcond=None)
        np.testing.assert_allclose(S @ coef, fit, rtol=0, atol=1e-10 * scale)




def run_status(S, dw, sigma, spec, threads):
    """igea_eqerr_run's own status (no verdict size), and whether rms and
    residual were left untouched."""
    m, N = S.shape
    opts = np.zeros(_capi.EQERR_OPT_LEN)
    lib.igea_eqerr_defaults(_lib.dptr(opts))
    opts[_capi.EQERR_OPT_THREADS] = threads
    lam, P, xhat, z = np.empty(N), np.empty((N, N), order="F"), np.empty(N), np.empty(N)
    rej, info = np.empty(N, dtype=np.intc), np.empty(_capi.STATS_INFO_LEN)
    res, rms = np.full(m, 7.0), np.full(3, 7.0)
    st = lib.igea_eqerr_run(m, N, _lib.dptr(S), m, _lib.dptr(dw), _lib.dptr(sigma), 1,
                            _lib.dptr(spec), _lib.dptr(opts), _lib.dptr(lam), _lib.dptr(P), N,
                            _lib.dptr(xhat), _lib.dptr(z), _lib.iptr(rej), _lib.dptr(info),
                            _lib.dptr(res), _lib.dptr(rms))
    return st, bool(np.all(res == 7.0) and np.all(rms == 7.0)), rms


def test_residual_squares_overflow_on_every_thread_count():
    """Residuals near 1.4e155 (dw scaled to 1e156, S and sigma by 1e150:
    the weighted normal equations stay of order one) have squares beyond
    DBL_MAX = 1.8e308, so the per-axis sums overflow: igea_eqerr_run says
    IGEA_EOVERFLOW on 1, 2 and 3 threads alike and leaves residual and rms
    untouched; scaled to 1e150 instead (squares near 2e298, sums below
    1e304) every thread count succeeds."""
    S, dw, sigma, spec = flight()
    S = np.asfortranarray(S * 1e150)
    big = np.full(len(dw), 1e150)
    for scale, want in ((1e150, 0), (1e156, _capi.EOVERFLOW)):
        d = dw / np.max(np.abs(dw)) * scale
        for t in (1, 2, 3):
            st, untouched, rms = run_status(S, d, big, spec, t)
            assert st == want, (scale, t)
            if want:
                assert untouched
            else:
                assert np.all(np.isfinite(rms)) and np.all(rms > 1e148)
