"""Contexts, scenes, structures and batches of rays."""

import ctypes
import os

import numpy as np

from . import _lib
from ._util import check, address, vectors, scalars, ray_count, lib
from .errors import InvalidArgumentError

INVALID_ID = 0xFFFFFFFF

_ISA_NAMES = ("auto", "scalar", "sse4.2", "avx2", "avx512")
_RTREE_BUILDS = ("insert", "str", "hilbert", "sah")
_RTREE_LAYOUTS = ("complete", "compact")
_STRATEGIES = ("min-volume", "min-surface", "min-overlap", "rstar", "rstar-surface")
_SPLITS = ("rstar", "quadratic")
_RTREE_TRAVERSALS = ("auto", "stackless", "ordered", "stack")
_KD_BUILDERS = ("nlogn", "nlog2n", "binned")
_KD_TRAVERSALS = ("htr", "btr", "sltr", "seq")
_EMBREE_QUALITIES = ("high", "medium", "low")


def version():
    return lib.tt_version().decode()


def accel_names():
    """The structures this build offers ("bruteforce", "rtree", ...)."""
    names, arr, i = [], lib.tt_accel_names(), 0
    while arr[i]:
        names.append(arr[i].decode())
        i += 1
    return names


def isa_best():
    return _ISA_NAMES[lib.tt_isa_best()]


def isa_supported(name):
    return bool(lib.tt_isa_supported(_choice("isa", name, _ISA_NAMES)))


def _choice(option, value, names):
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value < len(names):
        return value
    try:
        return names.index(value)
    except ValueError:
        raise InvalidArgumentError("%s: '%s' is not one of %s" % (option, value, ", ".join(names)),
                                   1) from None


class Context:
    """Threads (0: OpenMP's default) and the last error of the calls made
    through it. Scenes and structures keep their context alive."""

    def __init__(self, threads=0):
        opts = _lib.ContextOptions()
        lib.tt_context_options_default(ctypes.byref(opts))
        opts.threads = int(threads)
        handle = ctypes.c_void_p()
        st = lib.tt_context_create(ctypes.byref(opts), ctypes.byref(handle))
        check(st, None, "tt_context_create (threads %d)" % threads)
        self._h = handle

    @property
    def threads(self):
        return lib.tt_context_threads(self._h)

    @property
    def last_error(self):
        return lib.tt_context_last_error(self._h).decode("utf-8", "replace")

    def __del__(self):
        h = getattr(self, "_h", None)
        if h:
            lib.tt_context_destroy(h)
            self._h = None


_default_context = None


def default_context():
    global _default_context
    if _default_context is None:
        _default_context = Context()
    return _default_context


class Scene:
    """Triangles: Scene.load(path) (OBJ/PLY), Scene.from_arrays(vertices,
    indices) or Scene.from_memory(data, format)."""

    def __init__(self, handle, context):
        self._h = handle
        self.context = context

    @classmethod
    def load(cls, path, context=None):
        ctx = context or default_context()
        h = ctypes.c_void_p()
        check(lib.tt_scene_load(ctx._h, str(path).encode(), ctypes.byref(h)), ctx._h)
        return cls(h, ctx)

    @classmethod
    def from_memory(cls, data, format=None, name="memory", context=None):
        ctx = context or default_context()
        data = bytes(data)
        h = ctypes.c_void_p()
        check(lib.tt_scene_load_memory(ctx._h, name.encode(), format.encode() if format else None,
                                       data, len(data), ctypes.byref(h)), ctx._h)
        return cls(h, ctx)

    @classmethod
    def from_arrays(cls, vertices, indices, context=None):
        """vertices: (V, 3) floats; indices: (T, 3) integers < V."""
        ctx = context or default_context()
        v = np.ascontiguousarray(vertices, dtype=np.float32)
        i = np.asarray(indices)
        if i.size and (i.min() < 0 or i.max() > 0xFFFFFFFF):
            raise InvalidArgumentError("indices: values outside 0 .. 2^32-1", 1)
        i = np.ascontiguousarray(i, dtype=np.uint32)
        if v.ndim != 2 or v.shape[1] != 3:
            raise InvalidArgumentError("vertices: expected shape (V, 3), got %s" % (v.shape,), 1)
        if i.ndim != 2 or i.shape[1] != 3:
            raise InvalidArgumentError("indices: expected shape (T, 3), got %s" % (i.shape,), 1)
        h = ctypes.c_void_p()
        check(lib.tt_scene_create(ctx._h, address(v), v.shape[0], address(i), i.shape[0],
                                  ctypes.byref(h)), ctx._h)
        return cls(h, ctx)

    @property
    def triangle_count(self):
        return lib.tt_scene_triangle_count(self._h)

    @property
    def vertex_count(self):
        return lib.tt_scene_vertex_count(self._h)

    @property
    def bounds(self):
        lo, hi = (ctypes.c_float * 3)(), (ctypes.c_float * 3)()
        lib.tt_scene_bounds(self._h, lo, hi)
        return np.array(lo[:], np.float32), np.array(hi[:], np.float32)

    def triangles(self):
        """All triangles as a (T, 3, 3) float32 array, in load order."""
        n = self.triangle_count
        out = np.empty((n, 3, 3), np.float32)
        buf = (ctypes.c_float * 9)()
        for k in range(n):
            check(lib.tt_scene_triangle(self._h, k, buf), self.context._h)
            out[k] = np.frombuffer(buf, np.float32).reshape(3, 3)
        return out

    def __del__(self):
        h = getattr(self, "_h", None)
        if h:
            lib.tt_scene_destroy(h)
            self._h = None


class Hits:
    """Closest hits of a batch: t (+inf on a miss), u, v (barycentrics of
    vertices 1 and 2) as float32 arrays, prim (triangle id, INVALID_ID on a
    miss) as uint32, status (0 for a ray traced, else its tt_status);
    stats: the batch's traversal counts when asked for."""

    def __init__(self, t, u, v, prim, status, stats=None):
        self.t, self.u, self.v, self.prim, self.status, self.stats = t, u, v, prim, status, stats

    @property
    def hit(self):
        return self.prim != INVALID_ID

    def __len__(self):
        return len(self.t)


def _build_options(accel, isa, traversal, options):
    o = _lib.BuildOptions()
    lib.tt_build_options_default(ctypes.byref(o))
    o.accel = accel.encode()
    o.isa = _choice("isa", isa, _ISA_NAMES)
    r, k = o.rtree, o.kdtree
    if traversal is not None:
        if accel == "rtree":
            r.traversal = _choice("traversal", traversal, _RTREE_TRAVERSALS)
        elif accel == "kdtree":
            k.traversal = _choice("traversal", traversal, _KD_TRAVERSALS)
        else:
            raise InvalidArgumentError("traversal: only for rtree and kdtree", 1)
    rtree_opts = {
        "build": lambda x: setattr(r, "build", _choice("build", x, _RTREE_BUILDS)),
        "layout": lambda x: setattr(r, "layout", _choice("layout", x, _RTREE_LAYOUTS)),
        "strategy": lambda x: setattr(r, "strategy", _choice("strategy", x, _STRATEGIES)),
        "m": lambda x: setattr(r, "m", int(x)),
        "M": lambda x: setattr(r, "M", int(x)),
        "reinsert": lambda x: setattr(r, "reinsert", int(bool(x))),
        "reinsert_fraction": lambda x: setattr(r, "reinsert_fraction", float(x)),
        "reinsert_mode": lambda x: setattr(r, "reinsert_far",
                                           _choice("reinsert_mode", x, ("close", "far"))),
        "split": lambda x: setattr(r, "split", _choice("split", x, _SPLITS)),
    }
    kd_opts = {
        "builder": lambda x: setattr(k, "builder", _choice("builder", x, _KD_BUILDERS)),
        "dmin": lambda x: setattr(k, "dmin", -1 if x is None or x == "none" else int(x)),
        "cost_traversal": lambda x: setattr(k, "cost_traversal", float(x)),
        "cost_intersect": lambda x: setattr(k, "cost_intersect", float(x)),
        "empty_bonus": lambda x: setattr(k, "empty_bonus", float(x)),
        "max_depth": lambda x: setattr(k, "max_depth", int(x)),
        "shadow_hint": lambda x: setattr(k, "shadow_caster_hint",
                                         _choice("shadow_hint", x, ("primary", "caster"))),
    }
    embree_opts = {
        "quality": lambda x: setattr(o.embree, "quality",
                                     _choice("quality", x, _EMBREE_QUALITIES)),
    }
    table = {"rtree": rtree_opts, "kdtree": kd_opts, "embree": embree_opts}.get(accel, {})
    for key, value in options.items():
        if key not in table:
            raise TypeError("Accel('%s'): unknown option '%s'%s" % (
                accel, key, " (options: %s)" % ", ".join(sorted(table)) if table else ""))
        table[key](value)
    return o


class Accel:
    """An acceleration structure over a scene.

    Accel(scene, "rtree" | "kdtree" | "bruteforce" | "embree", isa="auto",
          traversal=None, **options)
    rtree options: build, layout, strategy, m, M, reinsert, reinsert_fraction,
    reinsert_mode, split; kdtree options: builder, dmin (None: the root's box
    only), cost_traversal, cost_intersect, empty_bonus, max_depth,
    shadow_hint; embree: quality ("high", "medium", "low"). Names as in
    `treetrace render --help`."""

    def __init__(self, scene, accel="rtree", isa="auto", traversal=None, **options):
        self.scene = scene
        self.context = scene.context
        opts = _build_options(accel, isa, traversal, options)
        h = ctypes.c_void_p()
        check(lib.tt_accel_build(self.context._h, scene._h, ctypes.byref(opts),
                                 ctypes.byref(h)), self.context._h)
        self._h = h

    def __del__(self):
        h = getattr(self, "_h", None)
        if h:
            lib.tt_accel_destroy(h)
            self._h = None

    @property
    def name(self):
        return lib.tt_accel_name(self._h).decode()

    @property
    def isa(self):
        return _ISA_NAMES[lib.tt_accel_isa(self._h)]

    @property
    def build_seconds(self):
        return lib.tt_accel_build_seconds(self._h)

    @property
    def memory_bytes(self):
        return lib.tt_accel_memory_bytes(self._h)

    def check(self):
        """Verifies the structure's invariants (InvariantError if broken)."""
        check(lib.tt_accel_check(self._h), self.context._h)

    def statistics(self):
        """The structure's statistics (height, nodes, SAH cost ...) as a dict."""
        out = {}

        def add(_user, key, value):
            out[key.decode()] = value

        fn = _lib.STAT_FN(add)
        check(lib.tt_accel_statistics(self._h, fn, None), self.context._h)
        return out

    # ------------------------------------------------------ saved structures

    def save(self, path, scene_name=None):
        """Saves the built structure to `path` (tt_accel_save; format in
        docs/accel-file.md). UnsupportedError for embree, saying why."""
        name = None if scene_name is None else str(scene_name).encode()
        check(lib.tt_accel_save(self._h, os.fsencode(path), name), self.context._h)

    @classmethod
    def load(cls, scene, path, isa="auto"):
        """The structure saved in `path` for `scene` (tt_accel_load): the file
        is mapped, not rebuilt, and traces bit for bit like the one saved. A
        damaged, foreign or hostile file raises with a message naming the
        file and what is wrong (ParseError, UnsupportedError; another
        scene's file: InvalidArgumentError)."""
        self = cls.__new__(cls)
        self.scene = scene
        self.context = scene.context
        h = ctypes.c_void_p()
        check(lib.tt_accel_load(self.context._h, scene._h, os.fsencode(path),
                                _choice("isa", isa, _ISA_NAMES), ctypes.byref(h)),
              self.context._h)
        self._h = h
        return self

    @property
    def loaded(self):
        """True for a structure that came from Accel.load."""
        return bool(lib.tt_accel_loaded(self._h))

    def locate(self, point):
        """The start hint for rays from `point` (kd-tree; else INVALID_ID)."""
        p = (ctypes.c_float * 3)(*[float(x) for x in point])
        return int(lib.tt_accel_locate(self._h, p))

    def _batch(self, origins, directions, tmin, tmax, start_hint, stats, image_width):
        n = ray_count(origins, directions)
        keep = []
        ra = _lib.RayArrays()
        a, ptrs, ra.org_stride = vectors(origins, n, "origins")
        keep.append(a)
        for k in range(3):
            ra.org[k] = ptrs[k]
        a, ptrs, ra.dir_stride = vectors(directions, n, "directions")
        keep.append(a)
        for k in range(3):
            ra.dir[k] = ptrs[k]
        a, ra.tmin, ra.tmin_stride = scalars(tmin, n, "tmin")
        keep.append(a)
        a, ra.tmax, ra.tmax_stride = scalars(tmax, n, "tmax")
        keep.append(a)
        bo = _lib.BatchOptions()
        lib.tt_batch_options_default(ctypes.byref(bo))
        if start_hint is not None:
            bo.start_hint = int(start_hint)
        if image_width:
            bo.image_width = int(image_width)
        counts = None
        if stats:
            counts = _lib.RayStats()
            bo.stats = ctypes.pointer(counts)
        return n, ra, bo, counts, keep

    def _finish(self, st, status, errors):
        if st != 0 and errors == "raise":
            check(st, self.context._h)

    def intersect(self, origins, directions, tmin=None, tmax=None, start_hint=None,
                  stats=False, errors="raise", image_width=0):
        """Closest hits of N rays on [tmin, tmax): origins and directions
        (N, 3) arrays, or one (3,) vector for every ray; tmin/tmax None
        (0 and +inf), a number or (N,) arrays. float32 arrays are used in
        place (any strides); others are converted once. Runs on the
        context's threads. A ray breaking the ray contract raises
        InvalidArgumentError naming the first bad index, unless
        errors="ignore": then its status is non-zero and its hit a miss.
        start_hint: the kd-tree's start node for every ray (Accel.locate of
        their common origin). image_width: the rays are the rows of an
        image that wide (as Camera.rays gives them): threads trace 16 x 16
        tiles, as the renderer does, which is faster for coherent rays."""
        if errors not in ("raise", "ignore"):
            raise ValueError("errors: 'raise' or 'ignore'")
        n, ra, bo, counts, keep = self._batch(origins, directions, tmin, tmax, start_hint, stats,
                                                 image_width)
        t = np.empty(n, np.float32)
        u = np.empty(n, np.float32)
        v = np.empty(n, np.float32)
        prim = np.empty(n, np.uint32)
        status = np.empty(n, np.intc)
        ha = _lib.HitArrays(address(t), 4, address(u), 4, address(v), 4, address(prim), 4)
        st = lib.tt_intersect_arrays(self._h, ctypes.byref(ra), n, ctypes.byref(ha),
                                     address(status), ctypes.byref(bo))
        del keep
        self._finish(st, status, errors)
        return Hits(t, u, v, prim, status, counts.as_dict() if counts is not None else None)

    def occluded(self, origins, directions, tmin=None, tmax=None, start_hint=None, stats=False,
                 errors="raise", return_status=False, image_width=0):
        """Whether anything lies on [tmin, tmax) of each ray: a bool (N,)
        array (and the status array with return_status=True; the counts too
        with stats=True). Arguments as for intersect."""
        if errors not in ("raise", "ignore"):
            raise ValueError("errors: 'raise' or 'ignore'")
        n, ra, bo, counts, keep = self._batch(origins, directions, tmin, tmax, start_hint, stats,
                                                 image_width)
        occ = np.empty(n, np.bool_)
        status = np.empty(n, np.intc)
        st = lib.tt_occluded_arrays(self._h, ctypes.byref(ra), n, address(occ), 1,
                                    address(status), ctypes.byref(bo))
        del keep
        self._finish(st, status, errors)
        out = [occ]
        if return_status:
            out.append(status)
        if stats:
            out.append(counts.as_dict())
        return out[0] if len(out) == 1 else tuple(out)

    def intersect1(self, origin, direction, tmin=0.0, tmax=float("inf"), start_hint=None):
        """One ray through tt_intersect1_ex: (t, u, v, prim)."""
        r = _lib.Ray((ctypes.c_float * 3)(*origin), tmin, (ctypes.c_float * 3)(*direction), tmax)
        h = _lib.Hit()
        args = _lib.TraceArgs(INVALID_ID if start_hint is None else start_hint, INVALID_ID, None)
        check(lib.tt_intersect1_ex(self._h, ctypes.byref(r), ctypes.byref(h), ctypes.byref(args)),
              self.context._h)
        return h.t, h.u, h.v, h.prim

    def occluded1(self, origin, direction, tmin=0.0, tmax=float("inf"), start_hint=None):
        """One ray through tt_occluded1_ex: True or False."""
        r = _lib.Ray((ctypes.c_float * 3)(*origin), tmin, (ctypes.c_float * 3)(*direction), tmax)
        o = ctypes.c_int()
        args = _lib.TraceArgs(INVALID_ID if start_hint is None else start_hint, INVALID_ID, None)
        check(lib.tt_occluded1_ex(self._h, ctypes.byref(r), ctypes.byref(o), ctypes.byref(args)),
              self.context._h)
        return bool(o.value)
