"""Accel.save / Accel.load: round trip of every structure (same hits bit
for bit), refusal of another scene's file, of a damaged file, and of
embree, each with a message naming the file."""
import os

import numpy as np
import pytest

import treetrace as tt

HERE = os.path.dirname(os.path.abspath(__file__))
BUNNY = os.path.join(HERE, "..", "..", "data", "bunny.ply")


def rays(scene, n=600, seed=3):
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    lo, hi = np.array(lo), np.array(hi)
    org = (lo + (hi - lo) * rng.uniform(-0.2, 1.2, (n, 3))).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    return org, d


@pytest.mark.parametrize("accel,options", [
    ("bruteforce", {}), ("rtree", {}), ("rtree", {"layout": "complete", "build": "insert"}),
    ("kdtree", {}), ("kdtree", {"builder": "binned"})])
def test_round_trip(tmp_path, accel, options):
    scene = tt.Scene.load(BUNNY)
    a = tt.Accel(scene, accel, **options)
    path = tmp_path / "s.tta"
    a.save(path, "bunny.ply")
    b = tt.Accel.load(scene, path)
    assert b.loaded and not a.loaded and b.name == accel
    b.check()
    org, d = rays(scene)
    ha, hb = a.intersect(org, d), b.intersect(org, d)
    for f in ("t", "u", "v", "prim"):
        assert np.array_equal(getattr(ha, f).view(np.uint32), getattr(hb, f).view(np.uint32))
    assert np.array_equal(a.occluded(org, d), b.occluded(org, d))


def test_refusals(tmp_path):
    scene = tt.Scene.load(BUNNY)
    path = tmp_path / "s.tta"
    tt.Accel(scene).save(path, "bunny.ply")
    other = tt.Scene.from_arrays(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),
                                 np.array([[0, 1, 2]], np.uint32))
    with pytest.raises(tt.Error, match="another scene.*bunny.ply"):
        tt.Accel.load(other, path)
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x40
    bad = tmp_path / "bad.tta"
    bad.write_bytes(bytes(data))
    with pytest.raises(tt.Error, match="bad.tta.*checksum"):
        tt.Accel.load(scene, bad)
    bad.write_bytes(bytes(data[:1000]))
    with pytest.raises(tt.Error, match="bad.tta.*truncated"):
        tt.Accel.load(scene, bad)
    if "embree" in tt.accel_names():
        with pytest.raises(tt.Error, match="cannot be saved"):
            tt.Accel(scene, "embree").save(tmp_path / "e.tta")


@pytest.mark.parametrize("accel", ["rtree", "kdtree"])
def test_loaded_structure_follows_edits(tmp_path, accel):
    """A loaded structure's arrays are a read-only mapping: an update after
    edits rebuilds it (never writes the file's pages) and it then answers
    for the edited scene like a fresh build."""
    scene = tt.Scene.load(BUNNY)
    path = tmp_path / "s.tta"
    tt.Accel(scene, accel).save(path, "bunny.ply")
    b = tt.Accel.load(scene, path)
    assert b.loaded and not b.updates_in_place
    pos = scene.vertices
    pos[:, 1] += 0.01 * np.sin(50 * pos[:, 0])
    scene.move_vertices(pos)
    with pytest.raises(tt.StaleError):
        b.intersect(*rays(scene))
    b.update()
    assert not b.loaded
    b.check()
    org, d = rays(scene)
    hb, hf = b.intersect(org, d), tt.Accel(scene, "bruteforce").intersect(org, d)
    assert np.array_equal(hb.prim, hf.prim) and np.array_equal(hb.t, hf.t)
