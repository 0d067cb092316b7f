"""The ctypes mirrors of the C structures have the C layout: the library's
own defaults functions fill them with the documented values and write
nothing past their end."""
import ctypes

import treetrace as tt
from treetrace import _lib

GUARD = 64


def filled_by(fn, cls):
    raw = (ctypes.c_uint8 * (ctypes.sizeof(cls) + GUARD))(*([0xCD] * (ctypes.sizeof(cls) + GUARD)))
    fn(ctypes.cast(raw, ctypes.POINTER(cls)))
    assert bytes(raw[ctypes.sizeof(cls):]) == b"\xcd" * GUARD, "%s: C wrote past the end" % cls
    return cls.from_buffer_copy(bytes(raw[:ctypes.sizeof(cls)]))


def test_build_options_layout():
    o = filled_by(_lib.lib.tt_build_options_default, _lib.BuildOptions)
    assert o.accel == b"rtree" and o.isa == 0
    r, k = o.rtree, o.kdtree
    assert (r.build, r.layout, r.strategy, r.m, r.M, r.reinsert) == (3, 1, 4, 2, 0, 1)
    assert abs(r.reinsert_fraction - 0.3) < 1e-6 and r.reinsert_far == 1
    assert (r.split, r.traversal, r.split_budget) == (0, 0, 0.0)
    assert (k.builder, k.dmin, k.max_depth, k.traversal, k.shadow_caster_hint) == (0, 0, 0, 0, 0)
    assert (k.cost_traversal, abs(k.cost_intersect - 0.2) < 1e-6) == (1.0, True)
    assert abs(k.empty_bonus - 0.2) < 1e-6
    assert o.embree.quality == 0


def test_render_and_batch_options_layout():
    o = filled_by(_lib.lib.tt_render_options_default, _lib.RenderOptions)
    assert (o.width, o.height, o.shadows, o.repeat, o.stats, o.keep_hits, o.keep_image,
            o.keep_pixel_stats, o.device, o.packets) == (1024, 1024, 1, 1, 0, 0, 0, 0, 0, 0)
    b = filled_by(_lib.lib.tt_batch_options_default, _lib.BatchOptions)
    assert b.start_hint == tt.INVALID_ID and not b.stats and b.chunk == 0
    assert b.image_width == 0 and b.packets == _lib.PACKETS["auto"] == 0
    assert not b.packet_stats
    c = filled_by(_lib.lib.tt_context_options_default, _lib.ContextOptions)
    assert c.threads == 0 and not c.on_error


def test_fixed_layouts():
    assert ctypes.sizeof(_lib.Ray) == 32 and ctypes.sizeof(_lib.Hit) == 16
    assert ctypes.sizeof(_lib.RayStats) == 48


def test_camera_layout(small_scene):
    cam = tt.Camera.frame(small_scene)
    lo, hi = small_scene.bounds
    assert cam.fov > 0 and cam.light is not None
    assert all(lo[i] <= cam.look[i] <= hi[i] for i in range(3))
