"""A scene's arrays at numpy speed: vertices, indices, triangles and
geometric normals, each from one C call (tt_scene_copy_arrays,
tt_scene_normals) instead of one call per triangle.

Scene inherits these from SceneArrays; they read the scene's current
state on every call (nothing is cached), so they stay right after edits."""

from __future__ import annotations

from typing import Tuple

import numpy as np

from ._util import address, check, lib
from .errors import InvalidArgumentError

_NULL = None


class SceneArrays:
    """Whole-array access to a Scene (mixed into treetrace.Scene)."""

    _h: object
    context: object

    def _copy(self, vertices: bool, indices: bool, triangles: bool):
        nv, nt = lib.tt_scene_vertex_count(self._h), lib.tt_scene_triangle_count(self._h)
        v = np.empty((nv, 3), np.float32) if vertices else None
        i = np.empty((nt, 3), np.uint32) if indices else None
        t = np.empty((nt, 3, 3), np.float32) if triangles else None
        check(lib.tt_scene_copy_arrays(self._h, address(v) if v is not None else _NULL, nv,
                                       address(i) if i is not None else _NULL,
                                       address(t) if t is not None else _NULL, nt),
              self.context._h, "tt_scene_copy_arrays")
        return v, i, t

    @property
    def vertices(self) -> np.ndarray:
        """The vertices as a (V, 3) float32 array (a copy), in load order.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> s.vertices
        array([[0., 0., 0.],
               [1., 0., 0.],
               [0., 1., 0.]], dtype=float32)
        """
        return self._copy(True, False, False)[0]

    @property
    def indices(self) -> np.ndarray:
        """The triangles' vertex ids as a (T, 3) uint32 array (a copy).

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> s.indices
        array([[0, 1, 2]], dtype=uint32)
        """
        return self._copy(False, True, False)[1]

    def arrays(self) -> Tuple[np.ndarray, np.ndarray]:
        """(vertices, indices) from one C call: what Scene.from_arrays takes.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> v, i = s.arrays()
        >>> v.shape, i.shape, tt.Scene.from_arrays(v, i).triangle_count
        ((3, 3), (1, 3), 1)
        """
        v, i, _ = self._copy(True, True, False)
        return v, i

    def triangles(self) -> np.ndarray:
        """All triangles as a (T, 3, 3) float32 array (triangle, vertex,
        coordinate), in load order, from one C call.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[2, 0, 1]])
        >>> s.triangles()[0]
        array([[0., 1., 0.],
               [0., 0., 0.],
               [1., 0., 0.]], dtype=float32)
        """
        return self._copy(False, False, True)[2]

    def normals(self, prims=None) -> np.ndarray:
        """Unit geometric normals, normalize(cross(v1 - v0, v2 - v0)), as
        float32 (..., 3): of every triangle (prims None) or of the triangle
        ids given (any shape, e.g. Hits.prim). A miss (INVALID_ID) and a
        degenerate triangle give (0, 0, 0).

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> s.normals()
        array([[0., 0., 1.]], dtype=float32)
        >>> s.normals([0, tt.INVALID_ID])
        array([[0., 0., 1.],
               [0., 0., 0.]], dtype=float32)
        """
        if prims is None:
            p = np.arange(lib.tt_scene_triangle_count(self._h), dtype=np.uint32)
        else:
            p = np.asarray(prims)
            if p.dtype != np.uint32:
                if p.size and (not np.issubdtype(p.dtype, np.integer)
                               or p.min() < 0 or p.max() > 0xFFFFFFFF):
                    raise InvalidArgumentError("prims: expected triangle ids (0 .. 2^32-1)", 1)
                p = p.astype(np.uint32)
        shape = p.shape
        flat = np.ascontiguousarray(p).reshape(-1)
        out = np.empty((flat.size, 3), np.float32)
        check(lib.tt_scene_normals(self._h, address(flat), flat.size, address(out)),
              self.context._h, "tt_scene_normals")
        return out.reshape(shape + (3,))
