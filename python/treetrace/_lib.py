"""Finding libtreetrace.so and declaring its C API to ctypes.

The structures below mirror include/treetrace/treetrace.h field by field;
tests/test_abi.py checks them against the library's own defaults functions
(values and sizes), so a header change that is not carried over here fails
the tests instead of corrupting memory."""

import ctypes
import ctypes.util
import os
import subprocess

_SONAME = "libtreetrace.so.0"


class RayStats(ctypes.Structure):
    _fields_ = [(name, ctypes.c_uint64)
                for name in ("rays", "nodes", "interior", "leaves", "boxes", "triangles")]

    def as_dict(self):
        return {name: int(getattr(self, name)) for name, _ in self._fields_}


class Hit(ctypes.Structure):
    _fields_ = [("t", ctypes.c_float), ("u", ctypes.c_float), ("v", ctypes.c_float),
                ("prim", ctypes.c_uint32)]


class Ray(ctypes.Structure):
    _fields_ = [("org", ctypes.c_float * 3), ("tmin", ctypes.c_float),
                ("dir", ctypes.c_float * 3), ("tmax", ctypes.c_float)]


class Allocator(ctypes.Structure):
    _fields_ = [("alloc", ctypes.c_void_p), ("realloc", ctypes.c_void_p),
                ("free", ctypes.c_void_p), ("user", ctypes.c_void_p)]


class ContextOptions(ctypes.Structure):
    _fields_ = [("threads", ctypes.c_int), ("allocator", Allocator),
                ("on_error", ctypes.c_void_p), ("on_error_user", ctypes.c_void_p)]


class RtreeOptions(ctypes.Structure):
    _fields_ = [("build", ctypes.c_int), ("layout", ctypes.c_int), ("strategy", ctypes.c_int),
                ("m", ctypes.c_int), ("M", ctypes.c_int), ("reinsert", ctypes.c_int),
                ("reinsert_fraction", ctypes.c_float), ("reinsert_far", ctypes.c_int),
                ("split", ctypes.c_int), ("traversal", ctypes.c_int),
                ("split_budget", ctypes.c_float)]


class KdtreeOptions(ctypes.Structure):
    _fields_ = [("builder", ctypes.c_int), ("dmin", ctypes.c_int),
                ("cost_traversal", ctypes.c_float), ("cost_intersect", ctypes.c_float),
                ("empty_bonus", ctypes.c_float), ("max_depth", ctypes.c_int),
                ("traversal", ctypes.c_int), ("shadow_caster_hint", ctypes.c_int)]


class EmbreeOptions(ctypes.Structure):
    _fields_ = [("quality", ctypes.c_int)]


class BuildOptions(ctypes.Structure):
    _fields_ = [("accel", ctypes.c_char_p), ("isa", ctypes.c_int),
                ("rtree", RtreeOptions), ("kdtree", KdtreeOptions), ("embree", EmbreeOptions)]


class TraceArgs(ctypes.Structure):
    _fields_ = [("start_hint", ctypes.c_uint32), ("end_hint", ctypes.c_uint32),
                ("stats", ctypes.POINTER(RayStats))]


class PacketCounts(ctypes.Structure):
    _fields_ = [(name, ctypes.c_uint64)
                for name in ("packets", "node_visits", "active_lanes", "fallback_rays")]


class BatchOptions(ctypes.Structure):
    _fields_ = [("start_hint", ctypes.c_uint32), ("stats", ctypes.POINTER(RayStats)),
                ("chunk", ctypes.c_uint32), ("image_width", ctypes.c_uint32),
                ("packets", ctypes.c_uint32), ("packet_stats", ctypes.POINTER(PacketCounts))]

# tt_batch_options.packets / tt_render_options.packets
PACKETS = {"auto": 0, "off": 1, "on": 2}


class RayArrays(ctypes.Structure):
    _fields_ = [("org", ctypes.c_void_p * 3), ("org_stride", ctypes.c_ssize_t),
                ("dir", ctypes.c_void_p * 3), ("dir_stride", ctypes.c_ssize_t),
                ("tmin", ctypes.c_void_p), ("tmin_stride", ctypes.c_ssize_t),
                ("tmax", ctypes.c_void_p), ("tmax_stride", ctypes.c_ssize_t)]


class HitArrays(ctypes.Structure):
    _fields_ = [("t", ctypes.c_void_p), ("t_stride", ctypes.c_ssize_t),
                ("u", ctypes.c_void_p), ("u_stride", ctypes.c_ssize_t),
                ("v", ctypes.c_void_p), ("v_stride", ctypes.c_ssize_t),
                ("prim", ctypes.c_void_p), ("prim_stride", ctypes.c_ssize_t)]


class Camera(ctypes.Structure):
    _fields_ = [("eye", ctypes.c_float * 3), ("look", ctypes.c_float * 3),
                ("up", ctypes.c_float * 3), ("fov_deg", ctypes.c_float),
                ("light", ctypes.c_float * 3), ("has_light", ctypes.c_int)]


class RenderOptions(ctypes.Structure):
    _fields_ = [("width", ctypes.c_uint32), ("height", ctypes.c_uint32),
                ("shadows", ctypes.c_int), ("repeat", ctypes.c_int), ("stats", ctypes.c_int),
                ("keep_hits", ctypes.c_int), ("keep_image", ctypes.c_int),
                ("keep_pixel_stats", ctypes.c_int), ("device", ctypes.c_int),
                ("packets", ctypes.c_uint32)]


class RenderSummary(ctypes.Structure):
    _fields_ = [("width", ctypes.c_uint32), ("height", ctypes.c_uint32),
                ("primary_rays", ctypes.c_uint64), ("primary_hits", ctypes.c_uint64),
                ("shadow_rays", ctypes.c_uint64), ("shadow_occluded", ctypes.c_uint64),
                ("trace_s", ctypes.c_double), ("trace_median_s", ctypes.c_double),
                ("primary_s", ctypes.c_double), ("shadow_s", ctypes.c_double),
                ("mrays_per_s", ctypes.c_double), ("primary_mrays_per_s", ctypes.c_double),
                ("shadow_mrays_per_s", ctypes.c_double), ("has_stats", ctypes.c_int),
                ("primary_stats", RayStats), ("shadow_stats", RayStats),
                ("threads", ctypes.c_int), ("device", ctypes.c_int),
                ("upload_s", ctypes.c_double), ("download_s", ctypes.c_double),
                ("device_name", ctypes.c_char * 64),
                ("packets", ctypes.c_int),
                ("primary_packets", PacketCounts), ("shadow_packets", PacketCounts)]


STAT_FN = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_char_p, ctypes.c_double)

_p = ctypes.c_void_p
_st = ctypes.c_int  # tt_status
_sz = ctypes.c_size_t

# name: (restype, argtypes)
_SIGNATURES = {
    "tt_strerror": (ctypes.c_char_p, [_st]),
    "tt_version": (ctypes.c_char_p, []),
    "tt_context_options_default": (None, [ctypes.POINTER(ContextOptions)]),
    "tt_context_create": (_st, [ctypes.POINTER(ContextOptions), ctypes.POINTER(_p)]),
    "tt_context_destroy": (None, [_p]),
    "tt_context_last_error": (ctypes.c_char_p, [_p]),
    "tt_context_threads": (ctypes.c_int, [_p]),
    "tt_scene_load": (_st, [_p, ctypes.c_char_p, ctypes.POINTER(_p)]),
    "tt_scene_load_memory": (_st, [_p, ctypes.c_char_p, ctypes.c_char_p, _p, _sz,
                                   ctypes.POINTER(_p)]),
    "tt_scene_create": (_st, [_p, _p, _sz, _p, _sz, ctypes.POINTER(_p)]),
    "tt_scene_destroy": (None, [_p]),
    "tt_scene_triangle_count": (_sz, [_p]),
    "tt_scene_vertex_count": (_sz, [_p]),
    "tt_scene_bounds": (None, [_p, ctypes.c_float * 3, ctypes.c_float * 3]),
    "tt_scene_triangle": (_st, [_p, _sz, ctypes.c_float * 9]),
    "tt_isa_name": (ctypes.c_char_p, [ctypes.c_int]),
    "tt_isa_from_name": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)]),
    "tt_isa_supported": (ctypes.c_int, [ctypes.c_int]),
    "tt_isa_best": (ctypes.c_int, []),
    "tt_build_options_default": (None, [ctypes.POINTER(BuildOptions)]),
    "tt_accel_names": (ctypes.POINTER(ctypes.c_char_p), []),
    "tt_accel_build": (_st, [_p, _p, ctypes.POINTER(BuildOptions), ctypes.POINTER(_p)]),
    "tt_accel_destroy": (None, [_p]),
    "tt_accel_name": (ctypes.c_char_p, [_p]),
    "tt_accel_build_seconds": (ctypes.c_double, [_p]),
    "tt_accel_isa": (ctypes.c_int, [_p]),
    "tt_accel_memory_bytes": (_sz, [_p]),
    "tt_accel_check": (_st, [_p]),
    "tt_accel_statistics": (_st, [_p, STAT_FN, _p]),
    "tt_accel_locate": (ctypes.c_uint32, [_p, ctypes.c_float * 3]),
    # saved structures
    "tt_accel_save": (_st, [_p, ctypes.c_char_p, ctypes.c_char_p]),
    "tt_accel_load": (_st, [_p, _p, ctypes.c_char_p, ctypes.c_int, ctypes.POINTER(_p)]),
    "tt_accel_loaded": (ctypes.c_int, [_p]),
    "tt_intersect1_ex": (_st, [_p, ctypes.POINTER(Ray), ctypes.POINTER(Hit),
                               ctypes.POINTER(TraceArgs)]),
    "tt_occluded1_ex": (_st, [_p, ctypes.POINTER(Ray), ctypes.POINTER(ctypes.c_int),
                              ctypes.POINTER(TraceArgs)]),
    "tt_batch_options_default": (None, [ctypes.POINTER(BatchOptions)]),
    "tt_intersect_arrays": (_st, [_p, ctypes.POINTER(RayArrays), _sz,
                                  ctypes.POINTER(HitArrays), _p, ctypes.POINTER(BatchOptions)]),
    "tt_occluded_arrays": (_st, [_p, ctypes.POINTER(RayArrays), _sz, _p, ctypes.c_ssize_t, _p,
                                 ctypes.POINTER(BatchOptions)]),
    "tt_camera_rays": (_st, [ctypes.POINTER(Camera), ctypes.c_uint32, ctypes.c_uint32, _p]),
    "tt_camera_frame_scene": (None, [_p, ctypes.POINTER(Camera)]),
    "tt_view_find": (_st, [_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(Camera)]),
    "tt_render_options_default": (None, [ctypes.POINTER(RenderOptions)]),
    "tt_render": (_st, [_p, _p, _p, ctypes.POINTER(Camera), ctypes.POINTER(RenderOptions),
                        ctypes.POINTER(_p)]),
    "tt_render_result_destroy": (None, [_p]),
    "tt_render_get_summary": (ctypes.POINTER(RenderSummary), [_p]),
    "tt_render_image": (_p, [_p]),
    "tt_render_hits": (_p, [_p, ctypes.POINTER(_sz)]),
    "tt_write_png": (_st, [_p, ctypes.c_char_p, _p, ctypes.c_uint32, ctypes.c_uint32]),
}


# Scene arrays in one call and hit normals (issue 21): tt_scene_copy_arrays,
# tt_scene_normals.
_SIGNATURES.update({
    "tt_scene_copy_arrays": (_st, [_p, _p, _sz, _p, _p, _sz]),
    "tt_scene_normals": (_st, [_p, _p, _sz, _p]),
})


def _candidates():
    """Where the library may be, in the order tried."""
    env = os.environ.get("TREETRACE_LIBRARY")
    if env:
        yield env
        return
    here = os.path.dirname(os.path.abspath(__file__))
    for name in (_SONAME, "libtreetrace.so"):
        yield os.path.join(here, name)
    # an installed copy the dynamic loader knows (ldconfig, LD_LIBRARY_PATH)
    yield _SONAME
    found = ctypes.util.find_library("treetrace")
    if found:
        yield found
    # an installed copy pkg-config knows (any prefix on PKG_CONFIG_PATH)
    try:
        libdir = subprocess.run(["pkg-config", "--variable=libdir", "treetrace"],
                                capture_output=True, text=True, check=True).stdout.strip()
        if libdir:
            yield os.path.join(os.path.normpath(libdir), _SONAME)
    except (OSError, subprocess.CalledProcessError):
        pass
    for prefix in ("/usr/local/lib", "/usr/local/lib64", "/usr/lib"):
        yield os.path.join(prefix, _SONAME)


def load():
    tried = []
    for path in _candidates():
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append("%s (%s)" % (path, e))
            continue
        for name, (restype, argtypes) in _SIGNATURES.items():
            fn = getattr(lib, name)
            fn.restype = restype
            fn.argtypes = argtypes
        lib.path = path
        return lib
    raise OSError("treetrace: cannot load the shared library libtreetrace.so; set "
                  "TREETRACE_LIBRARY to its path, or install it (cmake --install). Tried: "
                  + "; ".join(tried))


lib = load()
