"""Monte Carlo campaigns on a Dask cluster: igea.montecarlo split into
chunks of flights by first_flight, each chunk run by the C library on a
worker, the chunks' counts and per-flight tables merged.

Every flight has its own random stream (seed, flight index), so a chunk
computes exactly the rows the single-process run computes for its
flights; the merge recomputes what depends on all of them from the merged
table, in flight order, as igea_sim_montecarlo does (counts, means, rates
with igea_sim_interval, pooled verdicts with igea_sim_pool_ex). The result
equals the single-process run for any chunking and any number of workers:
bit for bit, except mean_size, which the library sums over the flights
and a merge can only rebuild from the chunks' means (to rounding).

Each task runs with BLAS on one thread (igea.blas_threads(1)), as Dask's
workers do by default and as the driver runs its own threads: OpenBLAS's
results depend on its thread count in the last digits (1e-10 relative in
T on a 360 x 21 model), so the single-process run a campaign equals is
igea.montecarlo under igea.blas_threads(1). A chunk whose worker dies is
recomputed by the scheduler (and retried up to three times on an error);
since a chunk's flights are a function of (seed, flight index) only, a
recomputed chunk is the same chunk and the result cannot change.

igea.campaign(grid, ...) runs a grid of studies (the operating
characteristic over error magnitudes and flight counts, say): every
chunk of every study is submitted at once, so the workers stay busy
across studies, and each study is merged as above.

dask.distributed is an optional dependency (pip install ./python[dask]);
any object with the Client's submit(fn, *args, **kwargs) -> future and
gather(futures) works as `client`.
"""
import itertools

import numpy as np

from . import _capi, _lib
from .sim import MonteCarloResult, _pool as _sim_pool, interval_cp, montecarlo
from .threads import blas_threads

_COUNTS = ("failed", "chi2_reject", "any_reject", "not_testable")


def _chunks(first, flights, chunk):
    return [(f, min(chunk, first + flights - f)) for f in range(first, first + flights, chunk)]


def _task(S, sigma, flights, first_flight, kw):
    """One chunk, on a worker: BLAS on one thread (see the module)."""
    with blas_threads(1):
        return montecarlo(S, sigma, flights, first_flight=first_flight, **kw)


def _interval(k, n):
    lohi = np.zeros(2)
    _lib.call("igea.campaign_montecarlo", "igea_sim_interval", float(k), float(n),
              _lib.dptr(lohi))
    return float(lohi[0]), float(lohi[1])


def _pool(table, size, alpha, verdict):
    """The pooled verdicts by the study's rule (the eqerr options the
    single-process run passes: alpha, verdict, overall_size)."""
    where = "igea.campaign_montecarlo"
    eq = _lib.options("eqerr", where, ("igea_sim_pool_ex", "eq_opts"), alpha=alpha,
                      overall_size=1,
                      verdict=_lib.choice(_capi.CHOICE_STATS_VERDICT, verdict, where, "verdict"))
    return _sim_pool(where, table, size, eq)


def _merge(parts, pool, alpha, verdict):
    """One MonteCarloResult from the chunks' results, in flight order."""
    n = sum(p.flights for p in parts)
    col = {k: np.concatenate([getattr(p, k) for p in parts])
           for k in ("chi2", "dof", "n_reject", "scale", "zmax")}
    cnt = {k: sum(getattr(p, k) for p in parts) for k in _COUNTS}
    testable = [f for f in range(n) if np.isfinite(col["scale"][f])]
    s = 0.0
    for f in testable:  # the library's order: flight by flight
        s += float(col["scale"][f])
    nt = len(testable)
    size = sum(p.mean_size * (p.flights - p.not_testable) for p in parts)
    outliers = sum(int(round(p.mean_outliers * p.flights)) for p in parts)
    table = np.zeros((n, _capi.SIM_MC_TABLE_COLS_Z), order="F")
    for k in col:
        table[:, getattr(_capi, "SIM_MC_TABLE_" + k.upper())] = col[k]
    return MonteCarloResult(
        flights=n, **cnt, mean_scale=s / nt if nt else float("nan"),
        mean_tested=float(sum(int(col["dof"][f]) for f in testable)) / nt if nt else 0.0,
        comp_tested=sum(p.comp_tested for p in parts).astype(np.intc),
        comp_reject=sum(p.comp_reject for p in parts).astype(np.intc), **col,
        rates={k: cnt[k] / n for k in _COUNTS}, ci99={k: _interval(cnt[k], n) for k in _COUNTS},
        pool=_pool(table, pool, alpha, verdict) if pool else None, verdict=verdict,
        mean_size=size / nt if nt else 0.0,
        scale_covered=sum(p.scale_covered for p in parts), mean_outliers=outliers / n,
        sigma_covered=sum(p.sigma_covered for p in parts),
        ci99_cp={k: interval_cp(cnt[k], n) for k in _COUNTS})


def _check_client(client):
    """The client: a dask.distributed Client (or any object with its
    submit and gather), or a scheduler address to connect to."""
    if client is None:
        raise ValueError("client: a dask.distributed Client (pip install ./python[dask])")
    if isinstance(client, str):
        try:
            from distributed import Client
        except ImportError as e:
            raise ImportError(f"client={client!r}: connecting to a Dask scheduler needs dask "
                              "and distributed (pip install ./python[dask])") from e
        return Client(client)
    if not (hasattr(client, "submit") and hasattr(client, "gather")):
        raise TypeError("client: needs submit() and gather(), as dask.distributed.Client")
    return client


def _check_chunk(chunk):
    if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
        raise ValueError(f"chunk: flights per task, an integer >= 1, got {chunk!r}")
    return int(chunk)


def _study(where, montecarlo_kwargs):
    """(S, sigma, flights, first, pool, alpha, verdict, kw) of one study,
    its arguments checked by a one-flight run here."""
    kw = dict(montecarlo_kwargs)
    missing = [k for k in ("S", "sigma", "flights") if k not in kw]
    if missing:
        raise TypeError(f"{where}: S, sigma and flights are keywords here (missing: "
                        f"{', '.join(missing)})")
    S, sigma, flights = kw.pop("S"), kw.pop("sigma"), kw.pop("flights")
    if isinstance(flights, bool) or int(flights) != flights or flights < 1:
        raise ValueError(f"flights: must be an integer >= 1, got {flights!r}")
    flights, first = int(flights), int(kw.pop("first_flight", 0))
    if first < 0:
        raise ValueError("first_flight: must be >= 0")
    pool, verdict = kw.pop("pool", None), kw.get("verdict", "seed")
    alpha = kw.get("alpha")
    if alpha is None:
        eq = np.zeros(_capi.EQERR_OPT_LEN)
        _lib.lib.igea_eqerr_defaults(_lib.dptr(eq))
        alpha = eq[_capi.EQERR_OPT_ALPHA]
    kw.setdefault("threads", 1)
    montecarlo(S, sigma, 1, first_flight=first, **kw)  # the arguments checked here first
    return S, sigma, flights, first, pool, alpha, verdict, kw


def _submit(client, study, chunk):
    S, sigma, flights, first, _, _, _, kw = study
    return [client.submit(_task, S, sigma, n, f, kw, pure=False, retries=3)
            for f, n in _chunks(first, flights, chunk)]


def campaign_montecarlo(client, chunk, **montecarlo_kwargs):
    """igea.montecarlo(**montecarlo_kwargs) run on a Dask client in chunks
    of `chunk` flights (>= 1): flights first_flight .. first_flight +
    flights - 1 split by flight index, one task per chunk (the model's
    arrays travel, nothing else), the results merged as described in the
    module. client: a dask.distributed Client, or a scheduler address
    ("tcp://host:8786"). threads (default 1 here: one task per worker
    core) is each task's. Returns the MonteCarloResult of the
    single-process run (with BLAS on one thread)."""
    client = _check_client(client)
    chunk = _check_chunk(chunk)
    study = _study("campaign_montecarlo", montecarlo_kwargs)
    futures = _submit(client, study, chunk)
    return _merge(client.gather(futures), study[4], study[5], study[6])


def _grid(grid):
    """The studies of a grid: a list of dicts as given, or a dict of
    name -> list of values expanded as the Cartesian product (the last
    name varying fastest)."""
    if isinstance(grid, dict):
        names = list(grid)
        for k in names:
            if isinstance(grid[k], (str, bytes)) or not hasattr(grid[k], "__iter__"):
                raise TypeError(f"grid[{k!r}]: a list of values")
        return [dict(zip(names, v)) for v in itertools.product(*(list(grid[k]) for k in names))]
    studies = list(grid)
    for i, g in enumerate(studies):
        if not isinstance(g, dict):
            raise TypeError(f"grid[{i}]: a dict of igea.montecarlo keywords")
    return studies


def campaign(grid, client=None, chunk=1000, **common):
    """A grid of Monte Carlo studies: each study is igea.montecarlo with the
    keywords `common` updated by one entry of `grid` (a list of dicts, or a
    dict of name -> values expanded as their Cartesian product, e.g.
    {"x": [[0, 2e-3], [0, 4e-3]], "flights": [1000, 4000]}). With a Dask
    `client`, every chunk of every study is submitted at once and each
    study merged as campaign_montecarlo does; without one, the studies run
    here in turn (the same results). Returns a list of (study, result): the
    grid entry (a dict) and its MonteCarloResult, in grid order."""
    studies = _grid(grid)
    if not studies:
        raise ValueError("grid: no study")
    if client is not None:
        client = _check_client(client)
    chunk = _check_chunk(chunk)
    checked = [_study(f"campaign: grid[{i}]", {**common, **g}) for i, g in enumerate(studies)]
    if client is None:
        futures = None
        parts = [[_task(*st[:2], n, f, st[7]) for f, n in _chunks(st[3], st[2], chunk)]
                 for st in checked]
    else:
        futures = [_submit(client, st, chunk) for st in checked]
        flat = client.gather([f for fs in futures for f in fs])
        parts, k = [], 0
        for fs in futures:
            parts.append(flat[k:k + len(fs)])
            k += len(fs)
    return [(g, _merge(p, st[4], st[5], st[6])) for g, p, st in zip(studies, parts, checked)]
