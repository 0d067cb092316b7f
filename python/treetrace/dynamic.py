"""Dynamic scenes from Python (issue 19): edits of a Scene and Accel.update.

    scene = tt.Scene.load("data/bunny.ply")
    accel = tt.Accel(scene)                      # the R-tree: updated in place
    ids = scene.add_triangles(tris)              # (N, 3, 3) or (N, 9) floats -> ids
    scene.remove_triangles(ids[:10])             # ids stay stable; freed ids are reused
    scene.set_triangles(ids[10:], tris[10:])     # whole triangles moved
    scene.move_vertices(positions)               # every vertex ((V, 3)), or
    scene.move_vertices(positions, vertex_ids)   # some of them
    accel.update()                               # one call brings it up to date

Between an edit and accel.update(), tracing through accel raises StaleError;
an edit or update overlapping traces on another thread raises BusyError
(the C library's threading contract, treetrace.h). Bad ids and non-finite
coordinates raise InvalidArgumentError and change nothing.

Kept in its own module (the C signatures it needs, its two error classes,
the methods it adds to Scene and Accel) beside the package's others."""

import ctypes

import numpy as np

from . import _lib, errors
from ._util import address, check
from .core import Accel, Scene
from .errors import InvalidArgumentError

lib = _lib.lib
_p, _st, _sz = ctypes.c_void_p, ctypes.c_int, ctypes.c_size_t

_SIGNATURES = {
    "tt_scene_add_triangles": (_st, [_p, _p, _sz, _p]),
    "tt_scene_remove_triangles": (_st, [_p, _p, _sz]),
    "tt_scene_set_triangles": (_st, [_p, _p, _p, _sz]),
    "tt_scene_move_vertices": (_st, [_p, _p, _p, _sz]),
    "tt_scene_triangle_alive": (ctypes.c_int, [_p, ctypes.c_uint32]),
    "tt_scene_live_triangle_count": (_sz, [_p]),
    "tt_scene_version": (ctypes.c_uint64, [_p]),
    "tt_accel_update": (_st, [_p]),
    "tt_accel_updates_in_place": (ctypes.c_int, [_p]),
}
for _name, (_res, _args) in _SIGNATURES.items():
    _fn = getattr(lib, _name)
    _fn.restype = _res
    _fn.argtypes = _args


class BusyError(errors.Error):
    """TT_ERR_BUSY: an edit or update overlapped traces on another thread."""
    status = 9


class StaleError(errors.Error):
    """TT_ERR_STALE: the scene was edited after the structure's last update."""
    status = 10


errors._BY_STATUS[BusyError.status] = BusyError
errors._BY_STATUS[StaleError.status] = StaleError


def _triangles(tris, name):
    t = np.ascontiguousarray(tris, dtype=np.float32)
    if t.ndim == 3 and t.shape[1:] == (3, 3):
        t = t.reshape(len(t), 9)
    if t.ndim != 2 or t.shape[1] != 9:
        raise InvalidArgumentError("%s: expected shape (N, 3, 3) or (N, 9), got %s"
                                   % (name, t.shape), 1)
    return np.ascontiguousarray(t)


def _ids(ids, name):
    i = np.asarray(ids)
    if i.ndim == 0:
        i = i.reshape(1)
    if i.ndim != 1:
        raise InvalidArgumentError("%s: expected a 1-D array of ids, got shape %s"
                                   % (name, i.shape), 1)
    if i.size and (i.min() < 0 or i.max() > 0xFFFFFFFF):
        raise InvalidArgumentError("%s: values outside 0 .. 2^32-1" % name, 1)
    return np.ascontiguousarray(i, dtype=np.uint32)


def add_triangles(self, triangles):
    """Adds triangles ((N, 3, 3) or (N, 9) floats); returns their ids (uint32),
    freed ids first (the most recently removed first).

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> s.add_triangles([[[0, 0, 1], [1, 0, 1], [0, 1, 1]]])
    array([1], dtype=uint32)
    """
    t = _triangles(triangles, "triangles")
    out = np.empty(len(t), np.uint32)
    check(lib.tt_scene_add_triangles(self._h, address(t), len(t), address(out)),
          self.context._h)
    return out


def remove_triangles(self, ids):
    """Removes live triangles by id; the ids become free for later additions.

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> s.remove_triangles([0]); s.is_alive(0), s.live_triangle_count
    (False, 0)
    """
    i = _ids(ids, "ids")
    check(lib.tt_scene_remove_triangles(self._h, address(i), len(i)), self.context._h)


def set_triangles(self, ids, triangles):
    """Moves whole triangles: ids[k] gets triangles[k] (shared vertices are
    copied first, so neighbours stay).

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> s.set_triangles([0], [[[0, 0, 2], [1, 0, 2], [0, 1, 2]]])
    >>> s.triangles()[0, :, 2]
    array([2., 2., 2.], dtype=float32)
    """
    i = _ids(ids, "ids")
    t = _triangles(triangles, "triangles")
    if len(t) != len(i):
        raise InvalidArgumentError("set_triangles: %d ids but %d triangles" % (len(i), len(t)), 1)
    check(lib.tt_scene_set_triangles(self._h, address(i), address(t), len(i)), self.context._h)


def move_vertices(self, positions, ids=None):
    """Moves vertices: positions (N, 3) for vertex ids (None: 0 .. N-1).

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> s.move_vertices([[0, 0, 5]], [2]); s.vertices[2]
    array([0., 0., 5.], dtype=float32)
    """
    p = np.ascontiguousarray(positions, dtype=np.float32)
    if p.ndim != 2 or p.shape[1] != 3:
        raise InvalidArgumentError("positions: expected shape (N, 3), got %s" % (p.shape,), 1)
    if ids is None:
        check(lib.tt_scene_move_vertices(self._h, None, address(p), len(p)), self.context._h)
        return
    i = _ids(ids, "ids")
    if len(i) != len(p):
        raise InvalidArgumentError("move_vertices: %d ids but %d positions" % (len(i), len(p)), 1)
    check(lib.tt_scene_move_vertices(self._h, address(i), address(p), len(i)), self.context._h)


def is_alive(self, triangle_id):
    """Whether the triangle id is live (added and not removed since).

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> s.is_alive(0), s.is_alive(7)
    (True, False)
    """
    return bool(lib.tt_scene_triangle_alive(self._h, int(triangle_id)))


def update(self):
    """Brings the structure up to date with its scene's edits (in place for the
    R-tree's compact layout, a rebuild for the others).

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> a = tt.Accel(s, "rtree")
    >>> s.move_vertices([[0, 0, -1], [1, 0, -1], [0, 1, -1]]); a.update()
    >>> float(a.intersect([[0.2, 0.2, 1]], (0, 0, -1)).t[0])
    2.0
    """
    check(lib.tt_accel_update(self._h), self.context._h)


Scene.add_triangles = add_triangles
Scene.remove_triangles = remove_triangles
Scene.set_triangles = set_triangles
Scene.move_vertices = move_vertices
Scene.is_alive = is_alive
Scene.live_triangle_count = property(lambda self: lib.tt_scene_live_triangle_count(self._h))
Scene.version = property(lambda self: int(lib.tt_scene_version(self._h)))
Accel.update = update
Accel.updates_in_place = property(lambda self: bool(lib.tt_accel_updates_in_place(self._h)))

# The RR*-tree's insertion strategy (issue 19) by name, beside the others.
from . import core as _core  # noqa: E402

if "rrstar" not in _core._STRATEGIES:
    _core._STRATEGIES = _core._STRATEGIES + ("rrstar",)
