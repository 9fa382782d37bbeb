# docs/api.md shows the files of tests/consumer/ (built and run against an installed prefix by
# CTest): every C++ block of the page must still be in one of them word for word.
import re


def test_api_examples_are_the_consumer_sources(root):
    page = (root / "docs/api.md").read_text()
    blocks = re.findall(r"```cpp\n(.*?)```", page, re.S)
    assert len(blocks) == 3
    sources = [p.read_text() for p in (root / "tests/consumer").glob("*.cpp")]
    for block in blocks:
        assert any(block in s for s in sources), block[:200]


def test_notebook_example_runs(root):
    import os
    import subprocess
    import sys
    env = dict(os.environ)
    p = subprocess.run([sys.executable, "docs/examples/notebook.py"], cwd=root, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert "collision ['link4', 'box']" in p.stdout
    assert "stopped: *Collision*  link4 / pillar" in p.stdout
