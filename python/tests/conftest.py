"""Fixtures of the Python tests: the repository root (the working directory of every test, so
scene paths read the same in the CLI and in Python) and the CLI binary built by
`cargo test --release` (target/release/magbubble), to compare against."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _binary() -> Path:
    env = os.environ.get("MAGBUBBLE_BIN")
    if env:
        return Path(env)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "magbubble"


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


@pytest.fixture(scope="session")
def cli():
    """cli(*args) → CompletedProcess of the magbubble binary (text, captured, cwd = repo root)."""
    exe = _binary()
    if not exe.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "magbubble"], cwd=ROOT, check=True)

    def call(*args, check=True):
        p = subprocess.run([str(exe), *map(str, args)], cwd=ROOT, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        if check and p.returncode != 0:
            raise AssertionError(f"magbubble {' '.join(map(str, args))} exited {p.returncode}:\n{p.stderr}")
        return p

    return call


@pytest.fixture(scope="session")
def cli_json(cli):
    def call(*args):
        return json.loads(cli(*args).stdout)

    return call
