"""Batches from Python: every result equals the C single-ray call's (bit for
bit) and agrees with a numpy brute-force reference; layouts are taken
without copies; bad rays raise with the library's message naming the index."""
import numpy as np
import pytest

import treetrace as tt
from treetrace import _util

from conftest import brute_force, random_rays, scene_path

VARIANTS = [("bruteforce", None), ("rtree", "stackless"), ("rtree", "ordered"),
            ("rtree", "stack"), ("rtree", "sah-compact"), ("kdtree", "htr"), ("kdtree", "btr"),
            ("kdtree", "sltr"), ("kdtree", "seq")]
if "embree" in tt.accel_names():
    VARIANTS.append(("embree", None))


def build(scene, accel, traversal):
    if traversal == "sah-compact":  # the bulk-loaded compact R-tree
        return tt.Accel(scene, accel, build="sah", layout="compact")
    return tt.Accel(scene, accel, traversal=traversal)


@pytest.fixture(scope="module")
def rays(small_scene):
    return random_rays(small_scene, 600)


@pytest.mark.parametrize("accel,traversal", VARIANTS)
def test_equals_single_ray_calls(small_scene, rays, accel, traversal):
    a = build(small_scene, accel, traversal)
    org, d, tmin, tmax = rays
    hits = a.intersect(org, d, tmin, tmax)
    occ = a.occluded(org, d, tmin, tmax)
    for i in range(0, len(org), 3):
        t, u, v, prim = a.intersect1(org[i], d[i], tmin[i], tmax[i])
        assert (hits.prim[i], hits.t[i], hits.u[i], hits.v[i]) == (prim, np.float32(t),
                                                                  np.float32(u), np.float32(v)), i
        assert occ[i] == a.occluded1(org[i], d[i], tmin[i], tmax[i]), i
    assert (hits.status == 0).all()


# Different triangles agree at a shared edge (or a tie), where the two t
# values differ only by rounding: tests/support/compare.h's TT_TEST_EDGE_REL,
# 100 times tighter than the conventions' 1e-4 (0.15 units at conference's
# distances). Embree (its own triangle test) is held to the 1e-4.
EDGE_REL = 1e-6
FOREIGN_REL = 1e-4
# numpy's float64 answer against the library's float32 watertight t on the
# same triangle: float32 rounding of the inputs and the result
NUMPY_SAME_REL = 1e-6


def agree(t, prim, ref_t, ref_p, same_rel=0.0, other_rel=EDGE_REL):
    """Per ray: both miss; or the same triangle with t within same_rel of
    ref_t (0: bit-identical); or other triangles with t within other_rel."""
    both_miss = (prim == tt.INVALID_ID) & (ref_p == tt.INVALID_ID)
    both_hit = (prim != tt.INVALID_ID) & (ref_p != tt.INVALID_ID)
    with np.errstate(invalid="ignore"):
        diff = np.abs(t.astype(np.float64) - np.asarray(ref_t, np.float64))
        scale = np.maximum(np.abs(np.asarray(ref_t, np.float64)), 1e-30)
        if same_rel == 0.0:
            same_ok = t.astype(np.float32).view(np.uint32) == \
                np.asarray(ref_t, np.float32).view(np.uint32)
        else:
            same_ok = diff <= same_rel * scale
        other_ok = diff <= other_rel * scale
    return both_miss | (both_hit & np.where(prim == ref_p, same_ok, other_ok))


def agree_exact(hits, ref):
    """The library-kernel rule against the library's bruteforce: the same
    triangle gives bit-identical t, u and v."""
    ok = agree(hits.t, hits.prim, ref.t, ref.prim)
    same = (hits.prim == ref.prim) & (hits.prim != tt.INVALID_ID)
    for a, b in ((hits.u, ref.u), (hits.v, ref.v)):
        ok &= ~same | (a.astype(np.float32).view(np.uint32) == b.astype(np.float32).view(np.uint32))
    return ok


@pytest.fixture(scope="module")
def numpy_reference(small_scene, small_camera, rays):
    """Ray sets with their numpy brute-force answers, computed once."""
    tris = small_scene.triangles()
    out = []
    for r in (rays, small_camera.rays(40, 40)):
        out.append((r, brute_force(tris, *r)))
    return out


@pytest.mark.parametrize("accel,traversal", VARIANTS)
def test_agrees_with_numpy_brute_force(small_scene, numpy_reference, accel, traversal):
    a = build(small_scene, accel, traversal)
    bf = tt.Accel(small_scene, "bruteforce")
    for (org, d, tmin, tmax), (ref_t, ref_p) in numpy_reference:
        hits = a.intersect(org, d, tmin, tmax)
        if accel == "embree":
            ok = agree(hits.t, hits.prim, ref_t, ref_p, FOREIGN_REL, FOREIGN_REL)
        else:
            ok = agree(hits.t, hits.prim, ref_t, ref_p, NUMPY_SAME_REL, EDGE_REL)
        assert ok.all(), "%d of %d rays disagree with numpy, first %d" % (
            (~ok).sum(), len(ok), np.flatnonzero(~ok)[0])
        if accel != "embree":
            ok = agree_exact(hits, bf.intersect(org, d, tmin, tmax))
            assert ok.all(), "%d of %d rays differ from the library's bruteforce, first %d" % (
                (~ok).sum(), len(ok), np.flatnonzero(~ok)[0])
        occ = a.occluded(org, d, tmin, tmax)
        assert (occ == np.isfinite(ref_t)).all()
        assert (hits.prim != tt.INVALID_ID).sum() > 0


def test_layouts_without_copies(small_scene, small_camera):
    a = tt.Accel(small_scene, "kdtree")
    org, d, tmin, tmax = small_camera.rays(32, 32)
    # float32 views of the (N, 8) ray buffer are used in place
    arr, ptrs, stride = _util.vectors(d, len(d), "directions")
    assert arr is d and stride == 32 and ptrs[0] == d.__array_interface__["data"][0]
    ref = a.intersect(org, d, tmin, tmax)
    # one origin for all rays (stride 0), tmin/tmax defaulted, float64 input
    one = a.intersect(small_camera.eye, d.astype(np.float64))
    assert (one.prim == ref.prim).all() and (one.t == ref.t).all()
    # Fortran order and reversed (negative strides)
    f = np.asfortranarray(d)
    assert (a.intersect(org, f).prim == ref.prim).all()
    rev = a.intersect(org[::-1], d[::-1], tmin[::-1], tmax[::-1])
    assert (rev.prim[::-1] == ref.prim).all() and (rev.u[::-1] == ref.u).all()
    # scalars for the interval
    assert (a.intersect(org, d, 0.0, np.inf).prim == ref.prim).all()


def test_threads_and_start_hint(small_scene, small_camera):
    org, d, tmin, tmax = small_camera.rays(48, 48)
    results = []
    for threads in (1, 2):
        ctx = tt.Context(threads=threads)
        assert ctx.threads == threads
        scene = tt.Scene.load(scene_path("bun_zipper_res4.ply"), context=ctx)
        a = tt.Accel(scene, "kdtree", traversal="sltr")
        hint = a.locate(small_camera.eye)
        h = a.intersect(org, d, tmin, tmax, start_hint=hint)
        for i in range(0, len(org), 17):
            assert h.prim[i] == a.intersect1(org[i], d[i], start_hint=hint)[3]
        results.append(h)
    assert (results[0].prim == results[1].prim).all() and (results[0].t == results[1].t).all()


def test_bad_rays_raise_with_index(small_scene, rays):
    a = tt.Accel(small_scene, "rtree")
    org, d, tmin, tmax = (x.copy() for x in rays)
    tmin[42] = -1.0
    d[99] = 0.0
    with pytest.raises(tt.InvalidArgumentError) as e:
        a.intersect(org, d, tmin, tmax)
    assert "ray 42 of 600" in str(e.value) and "negative tmin" in str(e.value)
    assert "2 bad rays" in str(e.value)
    assert e.value.status == 1 and isinstance(e.value, ValueError)
    h = a.intersect(org, d, tmin, tmax, errors="ignore")
    assert h.status[42] == 1 and h.status[99] == 1 and (np.delete(h.status, [42, 99]) == 0).all()
    assert h.prim[42] == tt.INVALID_ID and np.isinf(h.t[99])
    good = np.ones(len(org), bool)
    good[[42, 99]] = False
    ref = a.intersect(org[good], d[good], tmin[good], tmax[good])
    assert (h.prim[good] == ref.prim).all()
    occ, status = a.occluded(org, d, tmin, tmax, errors="ignore", return_status=True)
    assert not occ[42] and status[99] == 1
    with pytest.raises(tt.InvalidArgumentError, match="ray 42 of 600"):
        a.occluded(org, d, tmin, tmax)
    with pytest.raises(tt.InvalidArgumentError, match="zero direction"):
        a.intersect1(org[0], (0, 0, 0))
    with pytest.raises(tt.InvalidArgumentError, match="direction too short"):
        a.intersect1(org[0], (1e-30, 0, -1e-25))
    with pytest.raises(tt.InvalidArgumentError, match="rows"):
        a.intersect(org[:10], d)
    with pytest.raises(tt.InvalidArgumentError, match="shape"):
        a.intersect(org, d[:, :2])


def test_statistics(small_scene, small_camera):
    a = tt.Accel(small_scene, "rtree")
    org, d, tmin, tmax = small_camera.rays(16, 16)
    h = a.intersect(org, d, tmin, tmax, stats=True)
    assert h.stats["rays"] == 256 and h.stats["nodes"] > 256 and h.stats["triangles"] > 0
    occ, counts = a.occluded(org, d, tmin, tmax, stats=True)
    assert counts["rays"] == 256
    s = a.statistics()
    assert s["height"] >= 1 and s["nodes"] >= 1 and s["triangles"] == small_scene.triangle_count
    a.check()
    assert a.memory_bytes > 0 and a.isa in ("scalar", "sse4.2", "avx2", "avx512")


@pytest.mark.parametrize("accel", ["bruteforce", "rtree", "kdtree"])
def test_build_seconds(small_scene, accel):
    # measured by the library around the build: above 0, and within the
    # wall time of the whole constructor call
    import time
    t0 = time.perf_counter()
    a = tt.Accel(small_scene, accel)
    wall = time.perf_counter() - t0
    assert 0.0 < a.build_seconds <= wall
