"""The README's Python quick start runs as written (data/bunny.ply from the
repository root) and prints what its comments say."""
import os
import runpy

from conftest import ROOT
from readme_examples import example


def test_readme_python_quickstart(tmp_path, monkeypatch, capsys):
    code = example(os.path.join(ROOT, "README.md"), "quickstart.py")
    script = tmp_path / "quickstart.py"
    script.write_text(code.replace('"data/bunny.ply"',
                                   repr(os.path.join(ROOT, "data", "bunny.ply"))))
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(script), run_name="__main__")
    lines = capsys.readouterr().out.splitlines()
    assert "inf" in lines[0] and "4294967295" in lines[0]  # the last ray looks away: a miss
    assert len(lines[1].split()) >= 5  # a hit's (u, v) and unit normal
    assert lines[-1].startswith("[ True") and lines[-1].endswith("False]")
