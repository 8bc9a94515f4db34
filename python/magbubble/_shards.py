"""Running a sweep on any ``concurrent.futures.Executor`` (issue 33): the points are split into
shards (``shard="i/n"``, as ``--shard``), each shard is submitted to the executor and writes its
CSV into its own directory under ``out``, the shard CSVs are merged (as ``magbubble merge``),
and the command runs once more locally into ``out``: it resumes every point from the merged
file, so the result is the local one, bit for bit.

The executor may be a process pool, ``dask.distributed``'s ``Client.get_executor()`` or
submitit's SLURM executor; ``out`` must be on a file system its workers share (a local
cluster: any directory). A task sends only the scene's TOML text, its origin and the
arguments (no extension object crosses a process)."""

from __future__ import annotations

import os
import re
from typing import Any, Dict, List, Optional, Tuple

_SHARD_SUFFIX = re.compile(r"\.shard-\d+-of-\d+\.csv$")


def _command(name: str):
    import magbubble as mb

    return {"stability": mb.stability, "sweep": mb.sweep, "population": mb.population}[name]


def shard_task(command: str, text: str, origin: str, args: Tuple[Any, ...], kwargs: Dict[str, Any], out: str, shard: str) -> List[str]:
    """One shard, in a worker: the scene from its text, the command with ``shard``; returns the
    CSVs it wrote."""
    import magbubble as mb

    scene = mb.Scene.from_toml(text, origin)
    df = _command(command)(scene, *args, **kwargs, out=out, shard=shard, progress=False)
    return list(df.attrs["csv"])


def run_sharded(executor: Any, command: str, scene: Any, args: Tuple[Any, ...], kwargs: Dict[str, Any], out: Optional[str], shards: Optional[int], progress: Any):
    import tempfile

    import magbubble as mb
    from . import _magbubble as _ext

    n = int(shards) if shards is not None else max(2, os.cpu_count() or 2)
    if n < 1:
        raise ValueError(f"shards={shards}: need at least 1")
    text, origin = scene.to_toml(), scene.origin
    base = mb.Scene.from_toml(text, origin)
    with tempfile.TemporaryDirectory(prefix="magbubble-shards-") as tmp:
        root = os.fspath(out) if out is not None else os.path.join(tmp, "out")
        os.makedirs(root, exist_ok=True)
        futures = [
            executor.submit(shard_task, command, text, origin, tuple(args), dict(kwargs), os.path.join(root, f"shard-{i}-of-{n}"), f"{i}/{n}")
            for i in range(n)
        ]
        groups: Dict[str, List[str]] = {}
        for f in futures:
            for path in f.result():
                groups.setdefault(_SHARD_SUFFIX.sub(".csv", os.path.basename(path)), []).append(path)
        for name, parts in groups.items():
            target = os.path.join(root, name)
            if not os.path.exists(target):
                _ext.merge(parts, target)
        result = _command(command)(base, *args, **kwargs, out=root, shard="0/1", progress=progress)
        if out is None:
            result.attrs["csv"] = []
        return result
