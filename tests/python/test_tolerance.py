"""lens.tolerance: the same numbers as `lens tolerance --json`, and the
same to the bit in-process, over a spawned process pool and over a Dask
LocalCluster's executor; a forking pool refused."""

import concurrent.futures
import multiprocessing
import sys

import numpy as np
import pytest

import lens
from conftest import ROOT, cli_json

def same(a, b):
    """Equal to the bit, numpy arrays and lists alike."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple, np.ndarray)) or isinstance(b, (list, tuple, np.ndarray)):
        x, y = np.asarray(a, dtype=object), np.asarray(b, dtype=object)
        return x.shape == y.shape and all(same(p, q) for p, q in zip(x.ravel(), y.ravel()))
    return a == b


SPEC = ROOT / "lens-data" / "design" / "cooke-triplet.tolerance.json"


def test_matches_the_cli():
    here = lens.tolerance(SPEC, trials=40, seed=3)
    there, err = cli_json("tolerance", str(SPEC), "--trials", "40", "--seed", "3")
    assert there is not None, err
    assert same(here["monte_carlo"], there["monte_carlo"])
    assert same(here["sensitivity"], there["sensitivity"])
    assert same(here["nominal"], there["nominal"])
    for k in ("mean", "std", "yield"):
        assert isinstance(here["monte_carlo"][k], float)
    assert set(here["monte_carlo"]["percentiles"]) == {"p10", "p50", "p90", "p98"}


def test_a_spawned_process_pool_gives_the_same_trials():
    one = lens.tolerance(SPEC, trials=30, seed=5)
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(max_workers=2, mp_context=ctx) as ex:
        many = lens.tolerance(SPEC, trials=30, seed=5, executor=ex, chunks=3)
    assert same(many["monte_carlo"], one["monte_carlo"])


@pytest.mark.skipif(sys.platform == "win32", reason="no fork")
def test_a_forking_pool_is_refused():
    ctx = multiprocessing.get_context("fork")
    with concurrent.futures.ProcessPoolExecutor(max_workers=1, mp_context=ctx) as ex:
        with pytest.raises(lens.LensError, match="spawn"):
            lens.tolerance(SPEC, trials=4, executor=ex)


def test_a_dask_cluster_gives_the_same_trials():
    distributed = pytest.importorskip("distributed")
    one = lens.tolerance(SPEC, trials=40, seed=9)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            many = lens.tolerance(SPEC, trials=40, seed=9, executor=client.get_executor(), chunks=5)
    assert same(many["monte_carlo"], one["monte_carlo"])
    assert same(many["sensitivity"], one["sensitivity"])


def test_bad_input():
    with pytest.raises(lens.LensError, match="trials=0"):
        lens.tolerance(SPEC, trials=0)
    with pytest.raises(lens.OpticsError, match="cannot read"):
        lens.tolerance(ROOT / "no-such-file.json", trials=3)
