import os

import numpy as np
import pytest

import treetrace as tt

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = os.environ.get("TT_SCENES_DIR") or os.path.join(os.path.dirname(ROOT), "shared", "scenes")
BUNNY = os.path.join(ROOT, "data", "bunny.ply")


def scene_path(name):
    path = os.path.join(SCENES, name)
    if not os.path.exists(path):
        pytest.skip("shared scene %s is absent" % path)
    return path


@pytest.fixture(scope="session")
def small_scene():
    """The low-resolution bunny (a few thousand triangles) of the shared scenes."""
    return tt.Scene.load(scene_path("bun_zipper_res4.ply"))


@pytest.fixture(scope="session")
def small_camera():
    return tt.Camera.from_view(scene_path("views.tsv"), "bunny_res4:main")


def random_rays(scene, n, seed=7):
    """Origins in and around the scene box, random directions, some
    axis-parallel; tmin/tmax mixed (finite, infinite, empty)."""
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    ext = hi - lo
    org = (lo - 0.5 * ext + 2.0 * ext * rng.random((n, 3))).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    d[::7, 0] = 0.0
    d[::11] = (0.0, 0.0, -1.0)
    tmin = np.where(np.arange(n) % 5 == 0, 0.01 * rng.random(n), 0.0).astype(np.float32)
    tmax = np.where(np.arange(n) % 3 == 0, 0.3 * rng.random(n), np.inf).astype(np.float32)
    tmax[::101] = tmin[::101]
    return org, d, tmin, tmax


def brute_force(triangles, org, d, tmin, tmax):
    """A numpy reference in float64 (Moeller-Trumbore): closest t and
    triangle of every ray on [tmin, tmax), inf / INVALID_ID on a miss."""
    v0 = triangles[:, 0].astype(np.float64)
    e1 = triangles[:, 1].astype(np.float64) - v0
    e2 = triangles[:, 2].astype(np.float64) - v0
    n = len(org)
    best_t = np.full(n, np.inf)
    best_p = np.full(n, tt.INVALID_ID, np.uint32)
    for start in range(0, n, 64):
        o = org[start:start + 64, None, :].astype(np.float64)
        dd = d[start:start + 64, None, :].astype(np.float64)
        p = np.cross(dd, e2[None])
        det = np.einsum("rtk,tk->rt", p, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            s = o - v0[None]
            u = np.einsum("rtk,rtk->rt", s, p) * inv
            q = np.cross(s, e1[None])
            v = np.einsum("rtk,rtk->rt", dd.repeat(len(v0), 1), q) * inv
            t = np.einsum("tk,rtk->rt", e2, q) * inv
        lo = tmin[start:start + 64, None].astype(np.float64)
        hi = tmax[start:start + 64, None].astype(np.float64)
        ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= lo) & (t < hi)
        t = np.where(ok, t, np.inf)
        idx = np.argmin(t, axis=1)
        tt_min = t[np.arange(len(idx)), idx]
        best_t[start:start + 64] = tt_min
        best_p[start:start + 64] = np.where(np.isfinite(tt_min), idx, tt.INVALID_ID)
    return best_t, best_p
