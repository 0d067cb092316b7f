"""Scenes from files, memory and arrays; structure options; rendering to
arrays and PNG; the library's errors as Python exceptions."""
import os

import numpy as np
import pytest

import treetrace as tt

from conftest import BUNNY, scene_path

SQUARE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
SQUARE_I = np.array([[0, 1, 2], [0, 2, 3]])


def test_scene_from_arrays_and_triangles():
    s = tt.Scene.from_arrays(SQUARE_V, SQUARE_I)
    assert s.triangle_count == 2 and s.vertex_count == 4
    assert (s.triangles()[1] == SQUARE_V[[0, 2, 3]]).all()
    lo, hi = s.bounds
    assert (lo == 0).all() and (hi == (1, 1, 0)).all()
    a = tt.Accel(s, "kdtree")
    h = a.intersect([[0.75, 0.25, 2], [0.25, 0.75, 1], [2, 2, 1]], (0, 0, -1))
    assert list(h.prim) == [0, 1, tt.INVALID_ID] and list(h.t[:2]) == [2.0, 1.0]
    assert np.isclose(h.u[0] + h.v[0], 0.75)
    with pytest.raises(tt.InvalidArgumentError, match="refers to vertex 4"):
        tt.Scene.from_arrays(SQUARE_V, [[0, 1, 4]])
    with pytest.raises(tt.InvalidArgumentError, match="shape"):
        tt.Scene.from_arrays(SQUARE_V[:, :2], SQUARE_I)


def test_scene_from_memory_and_load_errors(tmp_path):
    obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    assert tt.Scene.from_memory(obj, "obj").triangle_count == 1
    with pytest.raises(tt.ParseError) as e:
        tt.Scene.from_memory(b"v 0 0 0\nf 1 2 x\n", "obj", name="broken.obj")
    assert "broken.obj" in str(e.value) and e.value.status == 4
    missing = str(tmp_path / "nothing.ply")
    with pytest.raises(tt.FileError) as e:
        tt.Scene.load(missing)
    assert missing in str(e.value) and isinstance(e.value, OSError)


def test_structure_options(small_scene):
    # Each option is read back (statistics) or, where no statistic shows it,
    # must change the tree built from the same scene: an option parsed and
    # then ignored fails here.
    def stats(accel, **opts):
        a = tt.Accel(small_scene, accel, **opts)
        a.check()
        return a.statistics()

    s = stats("rtree", strategy="rstar", M=8, m=3)
    assert s["M"] == 8 and s["m"] == 3
    insert = stats("rtree", build="insert")
    # one option at a time, so that each must change the tree by itself
    for opts in ({"strategy": "rstar"}, {"split": "quadratic"}, {"reinsert": False},
                 {"reinsert_mode": "close"}, {"reinsert_fraction": 0.5}):
        changed = stats("rtree", build="insert", **opts)
        assert changed["sah_cost"] != insert["sah_cost"], opts
    assert stats("rtree", build="str")["sah_cost"] != stats("rtree", build="sah")["sah_cost"]
    # split references: more references than triangles, the same tree otherwise
    split = stats("rtree", split_budget=0.25)
    assert split["references"] > stats("rtree")["references"]
    assert "layout_compact" in stats("rtree", build="sah", layout="compact")
    assert "layout_compact" not in stats("rtree", build="sah", layout="complete")
    kd = stats("kdtree")
    # the two exact builders build the same tree
    kd2 = stats("kdtree", builder="nlog2n")
    assert (kd2["sah_cost"], kd2["nodes"], kd2["references"]) == (kd["sah_cost"], kd["nodes"],
                                                                  kd["references"])
    assert stats("kdtree", builder="binned")["sah_cost"] != kd["sah_cost"]
    assert kd["dmin"] == -1  # auto with htr: no boxes below the root
    assert stats("kdtree", traversal="sltr")["dmin"] == 4
    assert stats("kdtree", dmin=None, traversal="sltr")["N_B"] == 1  # the root's box only
    s = stats("kdtree", dmin=2, cost_intersect=2.0)
    assert s["dmin"] == 2 and s["sah_cost"] != kd["sah_cost"]
    s = stats("kdtree", max_depth=12)
    assert s["depth_limit"] == 12 and s["depth_max"] <= 12
    # trace-time choices have no statistic: the structure must accept them
    tt.Accel(small_scene, "kdtree", shadow_hint="caster", traversal="sltr").check()
    with pytest.raises(tt.InvalidArgumentError) as e:
        tt.Accel(small_scene, "rtree", M=40)
    assert "M" in str(e.value)
    with pytest.raises(tt.InvalidArgumentError, match="unknown accel 'octree'"):
        tt.Accel(small_scene, "octree")
    with pytest.raises(tt.InvalidArgumentError, match="strategy"):
        tt.Accel(small_scene, "rtree", strategy="best")
    with pytest.raises(TypeError, match="unknown option 'dmin'"):
        tt.Accel(small_scene, "rtree", dmin=3)
    if "embree" in tt.accel_names():
        tt.Accel(small_scene, "embree", quality="medium")
        with pytest.raises(tt.InvalidArgumentError, match="quality"):
            tt.Accel(small_scene, "embree", quality="best")
    scalar = tt.Accel(small_scene, "rtree", isa="scalar")
    assert scalar.isa == "scalar"


def test_render_matches_batch_and_png(tmp_path, small_scene, small_camera):
    a = tt.Accel(small_scene, "kdtree")
    r = tt.render(small_scene, a, small_camera, 64, 48, hits=True)
    assert r.image.shape == (48, 64, 3) and r.image.dtype == np.uint8 and r.image.any()
    assert r.summary["primary_rays"] == 64 * 48 and r.summary["primary_mrays_per_s"] > 0
    org, d, tmin, tmax = small_camera.rays(64, 48)
    h = a.intersect(org, d, tmin, tmax)
    assert (h.prim.reshape(48, 64) == r.prim).all() and (h.t.reshape(48, 64) == r.t).all()
    assert r.summary["primary_hits"] == int(h.hit.sum())
    png = tmp_path / "bunny.png"
    tt.write_png(png, r.image)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(tt.FileError):
        tt.write_png(tmp_path / "no" / "such" / "dir.png", r.image)
    with pytest.raises(tt.ParseError, match="no view bunny:nowhere"):
        tt.Camera.from_view(scene_path("views.tsv"), "bunny:nowhere")
    with pytest.raises(tt.InvalidArgumentError):
        tt.Camera((0, 0, 0), (0, 0, 0)).rays(4, 4)


def test_bundled_bunny_loads():
    if not os.path.exists(BUNNY):
        pytest.skip("data/bunny.ply absent")
    s = tt.Scene.load(BUNNY)
    cam = tt.Camera.frame(s)
    img = tt.render(s, tt.Accel(s, "rtree"), cam, 32, 32).image
    assert img.shape == (32, 32, 3)
