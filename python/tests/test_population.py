"""population(), attenuation() (issue 33) and the executor= of stability/sweep/population:
sharded on a process pool or a dask.distributed LocalCluster, merged, equal to the local
result bit for bit."""

import multiprocessing
from concurrent.futures import ProcessPoolExecutor

import pandas as pd
import pytest

import magbubble as mb

BASE = """
[bubble]
radius = 3.8e-6
[shell]
c1 = 0.0
c2 = 0.0
surface_tension = 0.072
[liquid]
sound_speed = 1500.0
[drive]
amplitude = 0.2
frequency_hz = 1e6
[modes]
max_order = 2
"""
POP = BASE + """
[population]
median_radius = 4.1e-6
geometric_std = 1.05
bins = 3
concentration = 1e5
"""
FREQ = "1e6,1.2e6"


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "pop.toml"
    path.write_text(POP)
    return mb.Scene.load(path)


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    pd.testing.assert_frame_equal(a.reset_index(drop=True), b.reset_index(drop=True), check_exact=True)


def test_population_returns_the_csv_tables(scene, tmp_path):
    df = mb.population(scene, FREQ, eps_points=11, scan=4, out=tmp_path / "o", progress=False)
    assert list(df.columns) == ["frequency_hz", "eps_p", "fraction_unstable"]
    assert len(df) == 2 * 11
    bins = df.attrs["bins"]
    assert list(bins.columns) == ["frequency_hz", "radius", "weight", "critical_eps_p", "mode", "outcome", "windows", "note"]
    assert len(bins) == 2 * 3
    on_disk = pd.read_csv(tmp_path / "o" / "population.csv")
    _same(df, on_disk)
    assert df["fraction_unstable"].iloc[-1] == 1.0  # every bin has a threshold below 1 at 1 MHz


def test_one_bin_population_equals_stability(tmp_path):
    (tmp_path / "one.csv").write_text("radius,weight\n3.8e-6,1\n")
    (tmp_path / "one.toml").write_text(BASE + '\n[population]\ndistribution = "file"\nfile = "one.csv"\n')
    pop = mb.population(tmp_path / "one.toml", FREQ, scan=4, progress=False)
    st = mb.stability(mb.Scene.from_toml(BASE), FREQ, scan=4, progress=False)
    crit = pd.to_numeric(pop.attrs["bins"]["critical_eps_p"]).tolist()
    assert crit == st["critical"].tolist()


def test_attenuation_dataframe(scene):
    df = mb.attenuation(scene, "0.5e6:4e6:5:log")
    assert list(df.columns) == ["frequency_hz", "attenuation_db_per_cm", "backscatter_per_m_sr"]
    assert len(df) == 5 and (df["attenuation_db_per_cm"] > 0).all()


def test_process_pool_executor_equals_local(scene, tmp_path):
    local = mb.population(scene, FREQ, eps_points=11, scan=4, progress=False)
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as ex:
        remote = mb.population(scene, FREQ, eps_points=11, scan=4, executor=ex, shards=3, out=tmp_path / "p", progress=False)
        _same(local, remote)
        _same(local.attrs["bins"], remote.attrs["bins"])
        st_local = mb.stability(scene, FREQ, scan=4, progress=False)
        st_remote = mb.stability(scene, FREQ, scan=4, executor=ex, shards=2, progress=False)
        _same(st_local, st_remote)
        grid = {"drive.amplitude": [0.1, 0.2, 0.3]}
        sw = {"run.duration": 2e-6}
        a = mb.sweep(scene, grid, sw, progress=False)
        b = mb.sweep(scene, grid, sw, executor=ex, shards=2, progress=False)
        # wall_seconds is the one column no two runs share (a local rerun differs too)
        _same(a.drop(columns="wall_seconds"), b.drop(columns="wall_seconds"))


def test_dask_local_cluster_executor_equals_local(scene, tmp_path):
    distributed = pytest.importorskip("distributed")
    local = mb.population(scene, FREQ, eps_points=11, scan=4, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = mb.population(scene, FREQ, eps_points=11, scan=4, executor=client.get_executor(), shards=2, out=tmp_path / "d", progress=False)
    _same(local, remote)
    _same(local.attrs["bins"], remote.attrs["bins"])
