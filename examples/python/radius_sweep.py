"""A parameter sweep over the bubble radius from Python, three ways.

    python examples/python/radius_sweep.py [OUT_DIR]

1. `concurrent.futures.ThreadPoolExecutor` over `mb.run` and `mb.modes`: magbubble releases the
   GIL while it computes, so threads run the Rust core in parallel (no processes, no pickling),
   and each task can compute anything (here also the radial frequency).
2. `mb.sweep`: the grid of runs in Rust (rayon), one row of summary figures per run.
3. On a cluster: the Rust sweep with shards (`magbubble sweep … --shard i/n`, one process per
   job-array task, then `magbubble merge`), driven from Python with subprocess — the same
   files, resumable and mergeable; each shard can run on another node (or call
   `mb.sweep(..., out=DIR, shard="i/n")` in each task).
"""

import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pandas as pd

import magbubble as mb

ROOT = Path(__file__).resolve().parents[2]
SCENE = mb.Scene.load(ROOT / "scenes" / "coil_static.toml").with_overrides(
    {"modes.max_order": 8, "run.duration": 30e-6}
)
RADII = [6e-6, 8e-6, 10e-6, 12e-6, 15e-6, 20e-6]


def one_radius(radius: float) -> dict:
    scene = SCENE.with_overrides({"bubble.radius": radius})
    run = mb.run(scene, progress=False)
    f = mb.modes(scene)
    s = run.series
    shape = [c for c in s.columns if c[0] in "ab"]
    return {
        "radius_um": radius * 1e6,
        "f0_khz": f["radial"]["f_hz"] / 1e3,
        "status": run.status,
        "blow_up_us": run.blow_up["t"] * 1e6 if run.blow_up else None,
        "R_min_um": s["R"].min() * 1e6,
        "R_max_um": s["R"].max() * 1e6,
        "max_shape_um": s[shape].abs().to_numpy().max() * 1e6,
    }


def threads() -> pd.DataFrame:
    with ThreadPoolExecutor(max_workers=2) as pool:
        return pd.DataFrame(list(pool.map(one_radius, RADII)))


def rust_sweep() -> pd.DataFrame:
    df = mb.sweep(SCENE, grid={"bubble.radius": RADII}, progress=False)
    return df[["bubble.radius", "status", "t_blow_up", "R_min", "R_max", "max_shape", "max_shape_mode"]]


def shards(out: Path, n: int = 2) -> pd.DataFrame:
    """The radius grid in n shards (here one after another; on a cluster each is a job-array
    task with SLURM_ARRAY_TASK_ID/COUNT set instead of --shard), then merged."""
    exe = ROOT / "target" / "release" / "magbubble"  # `cargo build --release` builds it
    radii = ",".join(repr(r) for r in RADII)
    common = [str(exe), "sweep", str(ROOT / "scenes" / "coil_static.toml"), "--grid", f"bubble.radius={radii}",
              "--set", "modes.max_order=8", "--set", "run.duration=30e-6", "--out", str(out)]
    for i in range(n):
        subprocess.run([*common, "--shard", f"{i}/{n}"], check=True)
    parts = [str(out / f"sweep.shard-{i}-of-{n}.csv") for i in range(n)]
    subprocess.run([str(exe), "merge", *parts, "--out", str(out / "sweep.csv")], check=True)
    return pd.read_csv(out / "sweep.csv")


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "out" / "python-examples"
    out.mkdir(parents=True, exist_ok=True)
    print(threads().to_string(index=False))
    print(rust_sweep().to_string(index=False))
    merged = shards(out / "shards")
    print(merged[["bubble.radius", "status", "t_blow_up", "R_max"]].to_string(index=False))
