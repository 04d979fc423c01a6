"""Monte Carlo campaigns on a Dask cluster: igea.montecarlo split into
chunks of flights by first_flight, each chunk run by the C library on a
worker, the chunks' counts and per-flight tables merged.

Every flight has its own random stream (seed, flight index), so a chunk
computes exactly the rows the single-process run computes for its
flights; the merge recomputes what depends on all of them from the merged
table, in flight order, as igea_sim_montecarlo does (counts, means, rates
with igea_sim_interval, pooled verdicts with igea_sim_pool). The result
equals the single-process run for any chunking and any number of workers:
bit for bit, except mean_size, which the library sums over the flights
and a merge can only rebuild from the chunks' means (to rounding).

dask.distributed is an optional dependency (pip install ./python[dask]);
any object with the Client's submit(fn, *args, **kwargs) -> future and
gather(futures) works as `client`.
"""
import numpy as np

from . import _capi, _lib
from .sim import MonteCarloPool, MonteCarloResult, interval_cp, montecarlo

_COUNTS = ("failed", "chi2_reject", "any_reject", "not_testable")


def _chunks(first, flights, chunk):
    return [(f, min(chunk, first + flights - f)) for f in range(first, first + flights, chunk)]


def _interval(k, n):
    lohi = np.zeros(2)
    _lib.call("igea.campaign_montecarlo", "igea_sim_interval", float(k), float(n),
              _lib.dptr(lohi))
    return float(lohi[0]), float(lohi[1])


def _pool(table, size, alpha):
    n = table.shape[0]
    out = np.zeros(_capi.SIM_POOL_LEN)
    _lib.call("igea.campaign_montecarlo", "igea_sim_pool", n, _lib.dptr(table), n, int(size),
              float(alpha), _lib.dptr(out))
    f = _lib.fields(out, "SIM_POOL_", pools=int, failed=int, rate=float, ci99_lo=float,
                    ci99_hi=float)
    return MonteCarloPool(size=int(size), pools=f["pools"], failed=f["failed"], rate=f["rate"],
                          ci99=(f["ci99_lo"], f["ci99_hi"]))


def _merge(parts, pool, alpha, verdict):
    """One MonteCarloResult from the chunks' results, in flight order."""
    n = sum(p.flights for p in parts)
    col = {k: np.concatenate([getattr(p, k) for p in parts])
           for k in ("chi2", "dof", "n_reject", "scale")}
    cnt = {k: sum(getattr(p, k) for p in parts) for k in _COUNTS}
    testable = [f for f in range(n) if np.isfinite(col["scale"][f])]
    s = 0.0
    for f in testable:  # the library's order: flight by flight
        s += float(col["scale"][f])
    nt = len(testable)
    size = sum(p.mean_size * (p.flights - p.not_testable) for p in parts)
    outliers = sum(int(round(p.mean_outliers * p.flights)) for p in parts)
    table = np.zeros((n, _capi.SIM_MC_TABLE_COLS), order="F")
    for k in col:
        table[:, getattr(_capi, "SIM_MC_TABLE_" + k.upper())] = col[k]
    return MonteCarloResult(
        flights=n, **cnt, mean_scale=s / nt if nt else float("nan"),
        mean_tested=float(sum(int(col["dof"][f]) for f in testable)) / nt if nt else 0.0,
        comp_tested=sum(p.comp_tested for p in parts).astype(np.intc),
        comp_reject=sum(p.comp_reject for p in parts).astype(np.intc), **col,
        rates={k: cnt[k] / n for k in _COUNTS}, ci99={k: _interval(cnt[k], n) for k in _COUNTS},
        pool=_pool(table, pool, alpha) if pool else None, verdict=verdict,
        mean_size=size / nt if nt else 0.0,
        scale_covered=sum(p.scale_covered for p in parts), mean_outliers=outliers / n,
        sigma_covered=sum(p.sigma_covered for p in parts),
        ci99_cp={k: interval_cp(cnt[k], n) for k in _COUNTS})


def campaign_montecarlo(client, chunk, **montecarlo_kwargs):
    """igea.montecarlo(**montecarlo_kwargs) run on a Dask client in chunks
    of `chunk` flights (>= 1): flights first_flight .. first_flight +
    flights - 1 split by flight index, one task per chunk (the model's
    arrays travel, nothing else), the results merged as described in the
    module. threads (default 1 here: one task per worker core) is each
    task's. Returns the MonteCarloResult of the single-process run."""
    if client is None:
        raise ValueError("client: a dask.distributed Client (pip install ./python[dask])")
    if not (hasattr(client, "submit") and hasattr(client, "gather")):
        raise TypeError("client: needs submit() and gather(), as dask.distributed.Client")
    if isinstance(chunk, bool) or int(chunk) != chunk or chunk < 1:
        raise ValueError("chunk: flights per task, an integer >= 1")
    kw = dict(montecarlo_kwargs)
    args = [kw.pop(k) for k in ("S", "sigma", "flights") if k in kw]
    if len(args) != 3:
        raise TypeError("campaign_montecarlo: S, sigma and flights are keywords here")
    S, sigma, flights = args
    flights, first = int(flights), int(kw.pop("first_flight", 0))
    if flights < 1:
        raise ValueError("flights: must be >= 1")
    if first < 0:
        raise ValueError("first_flight: must be >= 0")
    pool, verdict = kw.pop("pool", None), kw.get("verdict", "seed")
    if pool and verdict != "seed":
        raise ValueError("pool: pools the seed's verdicts; only with verdict='seed'")
    alpha = kw.get("alpha")
    if alpha is None:
        eq = np.zeros(_capi.EQERR_OPT_LEN)
        _lib.lib.igea_eqerr_defaults(_lib.dptr(eq))
        alpha = eq[_capi.EQERR_OPT_ALPHA]
    kw.setdefault("threads", 1)
    montecarlo(S, sigma, 1, first_flight=first, **kw)  # the arguments checked here first
    futures = [client.submit(montecarlo, S, sigma, n, first_flight=f, pure=False, retries=3,
                             **kw)
               for f, n in _chunks(first, flights, int(chunk))]
    return _merge(client.gather(futures), pool, alpha, verdict)
