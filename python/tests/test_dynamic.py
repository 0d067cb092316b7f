"""Dynamic scenes from Python: edits, Accel.update, agreement with a fresh
bruteforce after every update, stable ids, errors that change nothing."""
import numpy as np
import pytest

import treetrace as tt

from conftest import random_rays


def fresh_agrees(scene, accel, rays):
    ref = tt.Accel(scene, "bruteforce").intersect(*rays)
    got = accel.intersect(*rays)
    with np.errstate(invalid="ignore"):  # inf - inf on rays both miss
        same = (got.prim == ref.prim) | (np.abs(got.t - ref.t) <= 1e-4 * np.abs(ref.t))
    return bool(np.all(same))


@pytest.mark.parametrize("accel", ["rtree", "kdtree"])
def test_edits_and_update(small_scene, accel):
    scene = tt.Scene.load(small_scene_path())  # its own copy: edits stay here
    a = tt.Accel(scene, accel)
    assert a.updates_in_place == (accel == "rtree")
    rays = random_rays(scene, 300)
    rest = scene.vertices
    rng = np.random.default_rng(3)
    for frame in range(1, 4):
        pos = rest.copy()
        pos[:, 0] += 0.002 * frame * np.sin(40 * pos[:, 1])
        scene.move_vertices(pos)
        with pytest.raises(tt.StaleError):
            a.intersect(*rays)
        a.update()
        a.check()
        assert fresh_agrees(scene, a, rays)
        live = [i for i in range(scene.triangle_count) if scene.is_alive(i)]
        gone = rng.choice(live, 10, replace=False)
        scene.remove_triangles(gone)
        tris = scene.triangles()[rng.integers(0, scene.triangle_count, 10)]
        tris[:, :, 0] += 0.01
        ids = scene.add_triangles(tris)
        assert set(ids.tolist()) == set(gone.tolist())  # freed ids come back
        a.update()
        a.check()
        assert fresh_agrees(scene, a, rays)


def small_scene_path():
    from conftest import scene_path
    return scene_path("bun_zipper_res4.ply")


def test_bad_edits_change_nothing(small_scene):
    scene = tt.Scene.load(small_scene_path())
    version = scene.version
    with pytest.raises(tt.InvalidArgumentError, match="not a triangle"):
        scene.remove_triangles([scene.triangle_count + 3])
    with pytest.raises(tt.InvalidArgumentError, match="twice"):
        scene.remove_triangles([1, 1])
    with pytest.raises(tt.InvalidArgumentError, match="non-finite"):
        scene.add_triangles(np.full((1, 9), np.nan))
    with pytest.raises(tt.InvalidArgumentError, match="not a vertex"):
        scene.move_vertices([[0, 0, 0]], [scene.vertex_count])
    assert scene.version == version


def test_remove_everything_and_back():
    tris = np.random.default_rng(1).random((50, 3, 3)).astype(np.float32)
    scene = tt.Scene.from_arrays(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
    a = tt.Accel(scene)
    ids = scene.add_triangles(tris)
    assert list(ids) == list(range(50))
    a.update()
    a.check()
    scene.remove_triangles(ids)
    assert scene.live_triangle_count == 0
    a.update()
    a.check()
    hits = a.intersect(np.array([[0.5, 0.5, -1.0]]), np.array([[0.0, 0.0, 1.0]]))
    assert hits.prim[0] == tt.INVALID_ID
    scene.add_triangles(tris)
    a.update()
    a.check()
