"""Scene arrays from one C call, hit normals, and Open3D-style cast_rays /
test_occlusions: equal to the per-triangle calls and to intersect/occluded,
ray by ray."""
import numpy as np
import pytest

import treetrace as tt

from conftest import brute_force, random_rays, scene_path

SQUARE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
SQUARE_I = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def test_arrays_match_per_triangle_calls(small_scene):
    v, i = small_scene.arrays()
    assert v.shape == (small_scene.vertex_count, 3) and v.dtype == np.float32
    assert i.shape == (small_scene.triangle_count, 3) and i.dtype == np.uint32
    tri = small_scene.triangles()
    assert (tri == v[i]).all()
    assert (small_scene.vertices == v).all() and (small_scene.indices == i).all()
    # the old way, one C call per triangle, gives the same
    buf = (tt._lib.ctypes.c_float * 9)()
    for k in (0, 1, len(tri) // 2, len(tri) - 1):
        assert tt._clib.tt_scene_triangle(small_scene._h, k, buf) == 0
        assert (np.frombuffer(buf, np.float32).reshape(3, 3) == tri[k]).all()
    again = tt.Scene.from_arrays(v, i)
    assert (again.triangles() == tri).all()


def test_from_arrays_layouts():
    for idx in (SQUARE_I, SQUARE_I.astype(np.int32), SQUARE_I.astype(np.int64),
                np.asfortranarray(SQUARE_I.astype(np.int32)), SQUARE_I.tolist()):
        s = tt.Scene.from_arrays(SQUARE_V, idx)
        assert (s.indices == SQUARE_I).all() and (s.vertices == SQUARE_V).all()
    s = tt.Scene.from_arrays(SQUARE_V.astype(np.float64)[:, :], SQUARE_I)
    assert (s.vertices == SQUARE_V).all()
    with pytest.raises(tt.InvalidArgumentError, match="outside"):
        tt.Scene.from_arrays(SQUARE_V, np.array([[0, -1, 2]], np.int32))
    # the caller's arrays may change afterwards: the library holds its own copy
    v = SQUARE_V.copy()
    s = tt.Scene.from_arrays(v, SQUARE_I)
    v[:] = 7
    assert (s.vertices == SQUARE_V).all()
    empty = tt.Scene.from_arrays(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
    assert empty.triangles().shape == (0, 3, 3) and empty.vertices.shape == (0, 3)


def test_normals():
    s = tt.Scene.from_arrays(SQUARE_V, SQUARE_I[:, ::-1])  # clockwise seen from +z
    assert (s.normals() == [[0, 0, -1], [0, 0, -1]]).all()
    n = s.normals(np.array([[1, tt.INVALID_ID], [0, 1]], np.uint32))
    assert n.shape == (2, 2, 3) and (n[0, 1] == 0).all() and (n[1, 0] == (0, 0, -1)).all()
    with pytest.raises(tt.InvalidArgumentError, match="prims\\[0\\] = 5"):
        s.normals([5])
    with pytest.raises(tt.InvalidArgumentError, match="triangle ids"):
        s.normals([-1])


def _numpy_normals(tri):
    n = np.cross((tri[:, 1] - tri[:, 0]).astype(np.float64), (tri[:, 2] - tri[:, 0]).astype(np.float64))
    return n / np.linalg.norm(n, axis=1, keepdims=True)


@pytest.mark.parametrize("accel,traversal", [("kdtree", "htr"), ("kdtree", "sltr"),
                                             ("rtree", None), ("bruteforce", None)])
def test_cast_rays_equals_intersect(small_scene, accel, traversal):
    a = tt.Accel(small_scene, accel, traversal=traversal)
    org, d, _, _ = random_rays(small_scene, 3000)
    rays = np.concatenate([org, d], axis=1)
    ans = a.cast_rays(rays)
    h = a.intersect(org, d, normals=True)
    assert set(ans) == {"t_hit", "geometry_ids", "primitive_ids", "primitive_uvs",
                        "primitive_normals"}
    hit = h.prim != tt.INVALID_ID
    assert hit.any() and (~hit).any()
    assert np.array_equal(ans["t_hit"], h.t) and np.array_equal(ans["primitive_ids"], h.prim)
    assert np.array_equal(ans["primitive_uvs"][hit], np.stack([h.u, h.v], 1)[hit])
    assert (ans["primitive_uvs"][~hit] == 0).all() and np.isinf(ans["t_hit"][~hit]).all()
    assert (ans["geometry_ids"][hit] == 0).all()
    assert (ans["geometry_ids"][~hit] == tt.INVALID_ID).all()
    assert np.array_equal(ans["primitive_normals"], h.normal)
    assert (h.normal[~hit] == 0).all()
    tri = small_scene.triangles()
    ref = _numpy_normals(tri[h.prim[hit]])
    assert np.allclose(h.normal[hit], ref, atol=1e-6)
    # the same closest hits as bruteforce in float64 numpy (t within rounding)
    bt, bp = brute_force(tri, org, d, np.zeros(len(org), np.float32),
                         np.full(len(org), np.inf, np.float32))
    assert np.array_equal(np.isfinite(bt), hit)
    assert np.allclose(ans["t_hit"][hit], bt[hit], rtol=1e-5)
    # the hit point from the uvs lies on the ray at t_hit
    u, v = ans["primitive_uvs"][hit, 0:1], ans["primitive_uvs"][hit, 1:2]
    t3 = tri[h.prim[hit]].astype(np.float64)
    p = (1 - u - v) * t3[:, 0] + u * t3[:, 1] + v * t3[:, 2]
    q = org[hit] + ans["t_hit"][hit, None].astype(np.float64) * d[hit]
    ext = np.ptp(small_scene.bounds, axis=0).max()
    assert np.abs(p - q).max() < 1e-4 * ext


def test_cast_rays_shapes_and_open3d_idioms(small_scene, small_camera):
    a = tt.Accel(small_scene, "kdtree")
    org, d, _, _ = small_camera.rays(16, 12)
    rays = np.concatenate([org, d], axis=1).reshape(12, 16, 6)
    ans = a.cast_rays(rays)
    assert ans["t_hit"].shape == (12, 16) and ans["primitive_uvs"].shape == (12, 16, 2)
    assert ans["primitive_normals"].shape == (12, 16, 3)
    assert isinstance(ans["t_hit"].numpy(), np.ndarray) and type(ans["t_hit"].numpy()) is np.ndarray
    flat = a.cast_rays(rays.reshape(-1, 6).astype(np.float64))  # converted once
    assert np.array_equal(flat["t_hit"].reshape(12, 16), ans["t_hit"])
    one = a.cast_rays(rays[3, 4])
    assert one["t_hit"].shape == () and one["t_hit"] == ans["t_hit"][3, 4]
    with pytest.raises(tt.InvalidArgumentError, match="\\(\\.\\.\\., 6\\)"):
        a.cast_rays(np.zeros((4, 3)))


def test_test_occlusions_equals_occluded(small_scene):
    a = tt.Accel(small_scene, "rtree")
    org, d, tmin, tmax = random_rays(small_scene, 2000, seed=3)
    rays = np.concatenate([org, d], axis=1)
    occ = a.test_occlusions(rays)
    assert np.array_equal(occ, a.occluded(org, d))
    occ2 = a.test_occlusions(rays, tnear=tmin, tfar=tmax)
    assert np.array_equal(occ2, a.occluded(org, d, tmin, tmax))
    assert occ2.dtype == np.bool_ and occ.any() and not occ.all()
    assert (occ2 <= occ).all()  # occluded on [tmin, tmax) implies on [0, inf)
    grid = a.test_occlusions(rays.reshape(40, 50, 6), tfar=tmax.reshape(40, 50))
    assert np.array_equal(grid.reshape(-1), a.occluded(org, d, None, tmax))
    with pytest.raises(tt.InvalidArgumentError, match="tfar"):
        a.test_occlusions(rays, tfar=tmax[:10])


def test_arrays_on_a_big_scene_match():
    """conference (331k triangles): one call gives what tt_scene_triangle gives."""
    s = tt.Scene.load(scene_path("conference.ply"))
    tri = s.triangles()
    v, i = s.arrays()
    assert tri.shape == (331179, 3, 3) and (tri == v[i]).all()


def test_raycasting_scene_like_open3d(small_scene):
    """Two meshes in one RaycastingScene: geometry ids and per-mesh triangle
    ids as Open3D gives them, the hits those of one structure over both."""
    v, i = small_scene.arrays()
    shift = np.array([0.5, 0, 0], np.float32)
    rc = tt.RaycastingScene(accel="kdtree")
    assert rc.add_triangles(v, i) == 0
    assert rc.add_triangles(v + shift, i.astype(np.int64)) == 1

    class LegacyMesh:  # Open3D's legacy TriangleMesh: .vertices, .triangles
        vertices, triangles = v + 2 * shift, i

    assert rc.add_triangles(LegacyMesh()) == 2
    both = tt.Scene.from_arrays(np.concatenate([v, v + shift, v + 2 * shift]),
                                np.concatenate([i, i + len(v), i + 2 * len(v)]))
    org, d, _, _ = random_rays(both, 2000, seed=11)
    rays = np.concatenate([org, d], 1)
    ans = rc.cast_rays(rays)
    ref = tt.Accel(both, "kdtree").intersect(org, d)
    hit = ref.prim != tt.INVALID_ID
    assert hit.any() and np.array_equal(ans["t_hit"], ref.t)
    n = small_scene.triangle_count
    assert np.array_equal(ans["geometry_ids"][hit], ref.prim[hit] // n)
    assert np.array_equal(ans["primitive_ids"][hit], ref.prim[hit] % n)
    assert (ans["geometry_ids"][~hit] == tt.INVALID_ID).all()
    assert (ans["primitive_ids"][~hit] == tt.INVALID_ID).all()
    assert np.array_equal(rc.test_occlusions(rays), hit)
    with pytest.raises(tt.InvalidArgumentError, match="nthreads"):
        rc.cast_rays(rays, nthreads=4)
    with pytest.raises(tt.InvalidArgumentError, match="outside"):
        rc.add_triangles(v, [[0, 1, len(v)]])
