"""python/examples/tutorial.py runs headless (MPLBACKEND=Agg), as in CI,
and does each of its steps: the images and the speed chart are written,
ambient occlusion lies in [0, 1] on hit pixels, every structure is timed."""
import os
import subprocess
import sys

import pytest

from conftest import ROOT, SCENES

pytest.importorskip("matplotlib")

TUTORIAL = os.path.join(ROOT, "python", "examples", "tutorial.py")


def test_tutorial_runs_headless(tmp_path):
    scene = os.path.join(SCENES, "bun_zipper_res4.ply")
    if not os.path.exists(scene):
        scene = os.path.join(ROOT, "data", "bunny.ply")
    env = dict(os.environ, MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join([os.path.join(ROOT, "python"),
                                          os.environ.get("PYTHONPATH", "")]))
    import treetrace
    if os.path.exists(treetrace.library_path):  # the same library, whatever the cwd
        env["TREETRACE_LIBRARY"] = os.path.abspath(treetrace.library_path)
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, TUTORIAL, "--scene", scene, "--size", "48x36",
                          "--samples", "4", "--out", str(out)], capture_output=True, text=True,
                         env=env, cwd=str(tmp_path), timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    text = run.stdout
    for step in ("1. load", "2. cast", "3. ambient occlusion", "4. show", "5. compare"):
        assert step in text
    assert "rays hit" in text and "kdtree sltr" in text and "rtree" in text
    openness = float(text.split("mean openness of the hit pixels: ")[1].split()[0])
    assert 0.0 < openness <= 1.0
    for name in ("tutorial-images.png", "tutorial-speed.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
