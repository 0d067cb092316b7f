"""The README's Python example runs as written (from the repository root,
where data/bunny.ply is) and does what it says."""
import os
import runpy

from conftest import ROOT
from readme_examples import example


def test_readme_python_example(tmp_path, monkeypatch, capsys):
    code = example(os.path.join(ROOT, "README.md"), "example.py")
    script = tmp_path / "example.py"
    script.write_text(code.replace('"data/bunny.ply"', repr(os.path.join(ROOT, "data", "bunny.ply"))))
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(script), run_name="__main__")
    out = capsys.readouterr().out
    assert "hits; first t" in out and "nodes per ray" in out
    assert "error:" in out and "missing.ply" in out
    assert (tmp_path / "bunny_py.png").read_bytes()[:4] == b"\x89PNG"
