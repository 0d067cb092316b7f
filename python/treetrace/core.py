"""Contexts, scenes, structures and batches of rays."""

from __future__ import annotations

import ctypes
import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _lib
from ._arrays import SceneArrays
from .raycast import RayCasting
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


def version() -> str:
    """The library's version string.

    >>> import treetrace as tt
    >>> tt.version().count(".") >= 2
    True
    """
    return lib.tt_version().decode()


def accel_names() -> List[str]:
    """The structures this build offers ("bruteforce", "rtree", ...).

    >>> import treetrace as tt
    >>> {"bruteforce", "rtree", "kdtree"} <= set(tt.accel_names())
    True
    """
    names, arr, i = [], lib.tt_accel_names(), 0
    while arr[i]:
        names.append(arr[i].decode())
        i += 1
    return names


def isa_best() -> str:
    """The fastest instruction set this CPU runs ("scalar" ... "avx512").

    >>> import treetrace as tt
    >>> tt.isa_best() in ("scalar", "sse4.2", "avx2", "avx512")
    True
    """
    return _ISA_NAMES[lib.tt_isa_best()]


def isa_supported(name: str) -> bool:
    """Whether this CPU runs the kernels of `name`.

    >>> import treetrace as tt
    >>> tt.isa_supported("scalar")
    True
    """
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
    through it. Scenes and structures keep their context alive.

    >>> import treetrace as tt
    >>> tt.Context(threads=1).threads
    1
    """

    def __init__(self, threads: int = 0) -> None:
        opts = _lib.ContextOptions()
        lib.tt_context_options_default(ctypes.byref(opts))
        opts.threads = int(threads)
        handle = ctypes.c_void_p()
        st = lib.tt_context_create(ctypes.byref(opts), ctypes.byref(handle))
        check(st, None, "tt_context_create (threads %d)" % threads)
        self._h = handle

    @property
    def threads(self) -> int:
        return lib.tt_context_threads(self._h)

    @property
    def last_error(self) -> str:
        return lib.tt_context_last_error(self._h).decode("utf-8", "replace")

    def __del__(self):
        h = getattr(self, "_h", None)
        if h:
            lib.tt_context_destroy(h)
            self._h = None


_default_context = None


def default_context() -> Context:
    """The context used when none is passed (OpenMP's default threads).

    >>> import treetrace as tt
    >>> tt.default_context() is tt.default_context()
    True
    """
    global _default_context
    if _default_context is None:
        _default_context = Context()
    return _default_context


class Scene(SceneArrays):
    """Triangles: Scene.load(path) (OBJ/PLY), Scene.from_arrays(vertices,
    indices) or Scene.from_memory(data, format). Whole arrays come back
    from one C call each: vertices, indices, arrays(), triangles(),
    normals().

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
    ...                          [[0, 1, 2], [0, 2, 3]])
    >>> s.triangle_count, s.vertex_count
    (2, 4)
    """

    def __init__(self, handle, context: Context) -> None:
        self._h = handle
        self.context = context

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"],
             context: Optional[Context] = None) -> "Scene":
        """An OBJ or PLY file (told apart by content). Errors name the file
        and the line or byte offset.

        >>> import treetrace as tt
        >>> tt.Scene.load("no/such/scene.ply")
        Traceback (most recent call last):
          ...
        treetrace.errors.FileError: no/such/scene.ply: cannot open: No such file or directory
        """
        ctx = context or default_context()
        h = ctypes.c_void_p()
        check(lib.tt_scene_load(ctx._h, str(path).encode(), ctypes.byref(h)), ctx._h)
        return cls(h, ctx)

    @classmethod
    def from_memory(cls, data: bytes, format: Optional[str] = None, name: str = "memory",
                    context: Optional[Context] = None) -> "Scene":
        """A scene from an OBJ or PLY file's bytes; `name` appears in errors.

        >>> import treetrace as tt
        >>> tt.Scene.from_memory(b"v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n", "obj").triangle_count
        1
        """
        ctx = context or default_context()
        data = bytes(data)
        h = ctypes.c_void_p()
        check(lib.tt_scene_load_memory(ctx._h, name.encode(), format.encode() if format else None,
                                       data, len(data), ctypes.byref(h)), ctx._h)
        return cls(h, ctx)

    @classmethod
    def from_arrays(cls, vertices, indices, context: Optional[Context] = None) -> "Scene":
        """vertices: (V, 3) floats; indices: (T, 3) integers < V. A C-ordered
        float32 vertex array and a C-ordered uint32 or int32 index array go
        to the library as they are, without a copy in Python (int32 is
        viewed as uint32 after a check for negative ids); other types and
        layouts are converted once. The library keeps its own copy (its
        kernels read a flat per-triangle one), so the arrays may change
        afterwards.

        >>> import numpy as np, treetrace as tt
        >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
        >>> tt.Scene.from_arrays(v, np.array([[0, 1, 2]], np.int32)).triangle_count
        1
        """
        ctx = context or default_context()
        v = np.ascontiguousarray(vertices, dtype=np.float32)
        i = np.asarray(indices)
        if i.dtype == np.int32 and i.flags.c_contiguous:
            if i.size and i.min() < 0:
                raise InvalidArgumentError("indices: values outside 0 .. 2^32-1", 1)
            i = i.view(np.uint32)
        elif i.dtype != np.uint32:
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
    def triangle_count(self) -> int:
        return lib.tt_scene_triangle_count(self._h)

    @property
    def vertex_count(self) -> int:
        return lib.tt_scene_vertex_count(self._h)

    @property
    def bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """The box of the triangles' vertices: (lo, hi) float32 (3,) arrays.

        >>> import treetrace as tt
        >>> tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 2, 0]], [[0, 1, 2]]).bounds
        (array([0., 0., 0.], dtype=float32), array([1., 2., 0.], dtype=float32))
        """
        lo, hi = (ctypes.c_float * 3)(), (ctypes.c_float * 3)()
        lib.tt_scene_bounds(self._h, lo, hi)
        return np.array(lo[:], np.float32), np.array(hi[:], np.float32)

    def __del__(self):
        h = getattr(self, "_h", None)
        # The garbage collector may finalize a context before the scene and
        # structures made with it (cycles, interpreter exit); freeing them
        # through a destroyed context would crash, so they are left then.
        if h and getattr(getattr(self, "context", None), "_h", None):
            lib.tt_scene_destroy(h)
        self._h = None


class Hits:
    """Closest hits of a batch: t (+inf on a miss), u, v (barycentrics of
    vertices 1 and 2) as float32 arrays, prim (triangle id, INVALID_ID on a
    miss) as uint32, status (0 for a ray traced, else its tt_status);
    stats: the batch's traversal counts when asked for; normal: (N, 3)
    float32 unit geometric normals with intersect(normals=True), else None.

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> h = tt.Accel(s).intersect([[0.2, 0.2, 1], [5, 5, 1]], (0, 0, -1))
    >>> h.hit, len(h)
    (array([ True, False]), 2)
    """

    normal: Optional[np.ndarray] = None

    def __init__(self, t, u, v, prim, status, stats=None):
        self.t, self.u, self.v, self.prim, self.status, self.stats = t, u, v, prim, status, stats

    @property
    def hit(self) -> np.ndarray:
        return self.prim != INVALID_ID

    def __len__(self) -> int:
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
        "split_budget": lambda x: setattr(r, "split_budget", float(x)),
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


class Accel(RayCasting):
    """An acceleration structure over a scene.

    Accel(scene, "rtree" | "kdtree" | "bruteforce" | "embree", isa="auto",
          traversal=None, **options)
    rtree options: build, layout, strategy, m, M, reinsert, reinsert_fraction,
    reinsert_mode, split, split_budget; kdtree options: builder, dmin (None: the root's box
    only), cost_traversal, cost_intersect, empty_bonus, max_depth,
    shadow_hint; embree: quality ("high", "medium", "low"). Names as in
    `treetrace render --help`. Rays: intersect/occluded (arrays of
    origins and directions), cast_rays/test_occlusions (Open3D's (N, 6)
    form), intersect1/occluded1 (one ray).

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> a = tt.Accel(s, "kdtree", traversal="sltr", dmin=2)
    >>> a.name, a.memory_bytes > 0
    ('kdtree', True)
    """

    def __init__(self, scene: Scene, accel: str = "rtree", isa: str = "auto",
                 traversal: Optional[str] = None, **options: Any) -> None:
        self.scene = scene
        self.context = scene.context
        opts = _build_options(accel, isa, traversal, options)
        h = ctypes.c_void_p()
        check(lib.tt_accel_build(self.context._h, scene._h, ctypes.byref(opts),
                                 ctypes.byref(h)), self.context._h)
        self._h = h

    def __del__(self):
        h = getattr(self, "_h", None)
        if h and getattr(getattr(self, "context", None), "_h", None):  # see Scene.__del__
            lib.tt_accel_destroy(h)
        self._h = None

    @property
    def name(self) -> str:
        return lib.tt_accel_name(self._h).decode()

    @property
    def isa(self) -> str:
        return _ISA_NAMES[lib.tt_accel_isa(self._h)]

    @property
    def build_seconds(self) -> float:
        return lib.tt_accel_build_seconds(self._h)

    @property
    def memory_bytes(self) -> int:
        return lib.tt_accel_memory_bytes(self._h)

    def check(self) -> None:
        """Verifies the structure's invariants (InvariantError if broken).

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tt.Accel(s, "rtree").check()
        """
        check(lib.tt_accel_check(self._h), self.context._h)

    def statistics(self) -> Dict[str, float]:
        """The structure's statistics (height, nodes, SAH cost ...) as a dict.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tt.Accel(s, "rtree").statistics()["triangles"]
        1.0
        """
        out = {}

        def add(_user, key, value):
            out[key.decode()] = value

        fn = _lib.STAT_FN(add)
        check(lib.tt_accel_statistics(self._h, fn, None), self.context._h)
        return out

    # ------------------------------------------------------ saved structures

    def save(self, path, scene_name=None):
        """Saves the built structure to `path` (tt_accel_save; format in
        docs/accel-file.md). UnsupportedError for embree, saying why.

        >>> import os, tempfile, treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> path = os.path.join(tempfile.mkdtemp(), "tri.tta")
        >>> tt.Accel(s, "rtree").save(path, "tri")
        >>> os.path.getsize(path) > 0
        True
        """
        name = None if scene_name is None else str(scene_name).encode()
        check(lib.tt_accel_save(self._h, os.fsencode(path), name), self.context._h)

    @classmethod
    def load(cls, scene, path, isa="auto"):
        """The structure saved in `path` for `scene` (tt_accel_load): the file
        is mapped, not rebuilt, and traces bit for bit like the one saved. A
        damaged, foreign or hostile file raises with a message naming the
        file and what is wrong (ParseError, UnsupportedError; another
        scene's file: InvalidArgumentError).

        >>> import os, tempfile, treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> path = os.path.join(tempfile.mkdtemp(), "tri.tta")
        >>> tt.Accel(s, "kdtree").save(path)
        >>> a = tt.Accel.load(s, path)
        >>> a.loaded, int(a.intersect([[0.2, 0.2, 1]], (0, 0, -1)).prim[0])
        (True, 0)
        """
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

    def locate(self, point) -> int:
        """The start hint for rays from `point` (kd-tree; else INVALID_ID).

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> isinstance(tt.Accel(s, "kdtree").locate((0.2, 0.2, 0.0)), int)
        True
        """
        p = (ctypes.c_float * 3)(*[float(x) for x in point])
        return int(lib.tt_accel_locate(self._h, p))

    def _batch(self, origins, directions, tmin, tmax, start_hint, stats, image_width,
               packets="auto"):
        if packets not in _lib.PACKETS:
            raise ValueError("packets: 'auto', 'on' or 'off'")
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
        bo.packets = _lib.PACKETS[packets]
        counts = None
        if stats:
            counts = _lib.RayStats()
            bo.stats = ctypes.pointer(counts)
        return n, ra, bo, counts, keep

    def _finish(self, st, status, errors):
        if st != 0 and errors == "raise":
            check(st, self.context._h)

    def intersect(self, origins, directions, tmin=None, tmax=None,
                  start_hint: Optional[int] = None, stats: bool = False, errors: str = "raise",
                  image_width: int = 0, normals: bool = False, packets: str = "auto") -> Hits:
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
        tiles, as the renderer does, which is faster for coherent rays.
        packets: "auto" (default) traces coherent groups of rays (a tile, a
        run of up to 256) together as packets where the structure has them,
        "on" always, "off" never; the results are the same bit for bit.
        normals=True: also Hits.normal, the hit triangles' unit geometric
        normals (Scene.normals; zeros on a miss).

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> h = tt.Accel(s, "kdtree").intersect([[0.2, 0.3, 1]], (0, 0, -1), normals=True)
        >>> h.t, h.prim, h.normal
        (array([1.], dtype=float32), array([0], dtype=uint32), array([[0., 0., 1.]], dtype=float32))
        """
        if errors not in ("raise", "ignore"):
            raise ValueError("errors: 'raise' or 'ignore'")
        n, ra, bo, counts, keep = self._batch(origins, directions, tmin, tmax, start_hint, stats,
                                                 image_width, packets)
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
        hits = Hits(t, u, v, prim, status, counts.as_dict() if counts is not None else None)
        if normals:
            hits.normal = self.scene.normals(prim)
        return hits

    def occluded(self, origins, directions, tmin=None, tmax=None,
                 start_hint: Optional[int] = None, stats: bool = False, errors: str = "raise",
                 return_status: bool = False, image_width: int = 0, packets: str = "auto"):
        """Whether anything lies on [tmin, tmax) of each ray: a bool (N,)
        array (and the status array with return_status=True; the counts too
        with stats=True). Arguments as for intersect.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tt.Accel(s, "rtree").occluded([[0.2, 0.2, 1]] * 2, (0, 0, -1), tmax=[2, 0.5])
        array([ True, False])
        """
        if errors not in ("raise", "ignore"):
            raise ValueError("errors: 'raise' or 'ignore'")
        n, ra, bo, counts, keep = self._batch(origins, directions, tmin, tmax, start_hint, stats,
                                                 image_width, packets)
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

    def intersect1(self, origin, direction, tmin: float = 0.0, tmax: float = float("inf"),
                   start_hint: Optional[int] = None) -> Tuple[float, float, float, int]:
        """One ray through tt_intersect1_ex: (t, u, v, prim).

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tt.Accel(s).intersect1((0.25, 0.5, 2), (0, 0, -1))
        (2.0, 0.25, 0.5, 0)
        """
        r = _lib.Ray((ctypes.c_float * 3)(*origin), tmin, (ctypes.c_float * 3)(*direction), tmax)
        h = _lib.Hit()
        args = _lib.TraceArgs(INVALID_ID if start_hint is None else start_hint, INVALID_ID, None)
        check(lib.tt_intersect1_ex(self._h, ctypes.byref(r), ctypes.byref(h), ctypes.byref(args)),
              self.context._h)
        return h.t, h.u, h.v, h.prim

    def occluded1(self, origin, direction, tmin: float = 0.0, tmax: float = float("inf"),
                  start_hint: Optional[int] = None) -> bool:
        """One ray through tt_occluded1_ex: True or False.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tt.Accel(s).occluded1((0.25, 0.5, 2), (0, 0, 1))
        False
        """
        r = _lib.Ray((ctypes.c_float * 3)(*origin), tmin, (ctypes.c_float * 3)(*direction), tmax)
        o = ctypes.c_int()
        args = _lib.TraceArgs(INVALID_ID if start_hint is None else start_hint, INVALID_ID, None)
        check(lib.tt_occluded1_ex(self._h, ctypes.byref(r), ctypes.byref(o), ctypes.byref(args)),
              self.context._h)
        return bool(o.value)
