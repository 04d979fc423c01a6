"""Monte Carlo campaigns on a real Dask LocalCluster (python/igea/campaign.py):
two worker processes, the flights split into chunks by flight index, the
merged result equal bit for bit to the single-process run (BLAS on one
thread, as every chunk runs; mean_size to rounding), also when a worker
process is killed in the middle of the run; igea.campaign over a grid of
studies equal to the studies run one by one."""
import os
import signal
import sys
import threading
import time

import numpy as np
import pytest

import igea

distributed = pytest.importorskip("distributed")

RNG = np.random.default_rng(20261201)
S = RNG.standard_normal((360, 21))
STUDY = dict(S=S, sigma=0.01, flights=403, sigma_w=1.3, seed=4, first_flight=11)


def same(a, b):
    for k, v in vars(a).items():
        w = getattr(b, k)
        if k == "mean_size":  # rebuilt from the chunks' means: to rounding
            assert v == pytest.approx(w, rel=1e-12, abs=0), k
        elif isinstance(v, np.ndarray):
            np.testing.assert_array_equal(v, w, err_msg=k)
        elif isinstance(v, float) and np.isnan(v):
            assert np.isnan(w), k
        else:
            assert v == w, k


def single(**kw):
    with igea.blas_threads(1):
        return igea.montecarlo(**kw)


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as c:
            yield c


@pytest.mark.parametrize("chunk", [50, 1000])
def test_cluster_equals_single_run(client, chunk):
    got = igea.campaign_montecarlo(client, chunk, **STUDY, pool=10)
    whole = single(**STUDY, pool=10)
    assert 0 < whole.failed < whole.flights and got.pool.pools == 40
    same(got, whole)


def test_montecarlo_with_a_client(client):
    same(igea.montecarlo(**STUDY, client=client, chunk=100), single(**STUDY))
    with pytest.raises(ValueError, match="chunk: .*only with client"):
        igea.montecarlo(**STUDY, chunk=100)
    with pytest.raises(ValueError, match="progress: not with client"):
        igea.montecarlo(**STUDY, client=client, progress=True)


def test_cluster_small_chunks(client):
    kw = dict(STUDY, flights=45)
    same(igea.campaign_montecarlo(client, 7, **kw), single(**kw))


def test_a_killed_worker_changes_nothing(client):
    """One of the two worker processes is killed (SIGKILL) after a few
    chunks are done: the scheduler recomputes its chunks elsewhere (or on
    the worker its nanny restarts) and the merged result is unchanged."""
    kw = dict(S=S, sigma=0.01, flights=8000, seed=9)
    out, errors = {}, []

    def run():
        try:
            out["r"] = igea.campaign_montecarlo(client, 400, **kw)
        except Exception as e:  # reported below
            errors.append(e)

    def done_tasks(dask_scheduler):
        return sum(1 for t in dask_scheduler.tasks.values() if t.state == "memory")

    pids = client.run(os.getpid)
    t = threading.Thread(target=run)
    t.start()
    deadline = time.monotonic() + 120
    while client.run_on_scheduler(done_tasks) < 3 and time.monotonic() < deadline:
        time.sleep(0.01)
    done_at_kill = client.run_on_scheduler(done_tasks)
    os.kill(sorted(pids.values())[0], signal.SIGKILL)
    t.join(300)
    assert not t.is_alive() and not errors, errors
    assert 3 <= done_at_kill < 20, done_at_kill  # killed in the middle of the run
    same(out["r"], single(**kw))


def test_grid_equals_the_studies_one_by_one(client):
    grid = {"x": [np.zeros(21), np.r_[np.zeros(5), 6.0, np.zeros(15)]], "flights": [30, 80]}
    common = dict(S=S, sigma=0.01, seed=5)
    for c in (client, None):
        res = igea.campaign(grid, client=c, chunk=40, **common)
        assert [list(g) for g, _ in res] == [["x", "flights"]] * 4
        assert [g["flights"] for g, _ in res] == [30, 80, 30, 80]  # the last name fastest
        for g, r in res:
            same(r, single(**common, **g))
    # the second magnitude is seen: more rejections than under H0
    assert res[3][1].failed > res[1][1].failed


def test_grid_as_a_list_and_its_errors():
    studies = [dict(flights=30, seed=1), dict(flights=20, seed=2, sigma_w=2.0)]
    res = igea.campaign(studies, chunk=9, S=S, sigma=0.01)
    for (g, r), st in zip(res, studies):
        assert g is st
        same(r, single(S=S, sigma=0.01, **st))
    with pytest.raises(ValueError, match="grid: no study"):
        igea.campaign([], S=S, sigma=0.01)
    with pytest.raises(TypeError, match=r"grid\[1\]"):
        igea.campaign([dict(flights=3), 5], S=S, sigma=0.01)
    with pytest.raises(TypeError, match=r"grid\['seed'\]"):
        igea.campaign({"seed": 3}, S=S, sigma=0.01, flights=3)
    with pytest.raises(TypeError, match="missing: flights"):
        igea.campaign([dict(seed=1)], S=S, sigma=0.01)
    with pytest.raises(ValueError, match="chunk"):
        igea.campaign([dict(flights=3)], chunk=0, S=S, sigma=0.01)
    with pytest.raises(ValueError, match=r"grid\[0\]|sigma"):
        igea.campaign([dict(flights=3, sigma=-1.0)], S=S, sigma=0.01)


def test_an_address_without_distributed(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    with pytest.raises(ImportError, match=r"pip install \./python\[dask\]"):
        igea.campaign_montecarlo("tcp://127.0.0.1:8786", 10, **STUDY)
