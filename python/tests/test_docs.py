"""The Python examples of README.md and docs/python.md run (read from the docs themselves, so
the docs and this test cannot drift), and the README's install line is a `pip install` line."""

import re

import pytest

from conftest import ROOT


def _blocks(doc):
    text = (ROOT / doc).read_text()
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


@pytest.mark.parametrize("doc", ["README.md", "docs/python.md"])
def test_python_examples_of_the_docs_run(doc, tmp_path, monkeypatch):
    blocks = _blocks(doc)
    assert blocks, f"no python block in {doc}"
    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    monkeypatch.chdir(tmp_path)
    env = {}  # shared by the blocks of a document, as a reader running them in order
    for code in blocks:
        exec(compile(code, doc, "exec"), env)
    if doc == "docs/python.md":
        assert env["run"].status == "blow_up" and env["run"].blow_up["mode"] == "a16"
        assert abs(env["run"].blow_up["t"] - 2.06e-5) < 0.01e-5
        assert abs(env["peak"] - 4.4e6) < 0.2e6 and abs(env["f0"] - 4.41e6) < 0.01e6
        assert abs(env["levels"]["fundamental_db"] + 29.9) < 0.05


def test_readme_installs_with_one_pip_line():
    lines = [l.strip() for l in (ROOT / "README.md").read_text().splitlines()]
    assert "pip install ./python" in lines
    assert "bash .ci/run" in lines
