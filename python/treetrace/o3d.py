"""RaycastingScene: Open3D's ray casting interface over treetrace, so that
code written for o3d.t.geometry.RaycastingScene runs with one line changed:

    scene = o3d.t.geometry.RaycastingScene()   ->   scene = tt.RaycastingScene()

add_triangles takes (vertices, indices) arrays or a mesh (Open3D's tensor
or legacy TriangleMesh, or anything with vertices/triangles arrays) and
returns the geometry's id; cast_rays and test_occlusions take the same
(..., 6) rays and return the same keys (see treetrace.raycast). The meshes
become one treetrace Scene and one structure, built on the first query
after a change. create_rays_pinhole, count_intersections,
list_intersections and the closest-point queries have no counterpart."""

from __future__ import annotations

from typing import Any, Dict, List, Optional

import numpy as np

from .core import INVALID_ID, Accel, Context, Scene
from .errors import InvalidArgumentError


def _array(x: Any) -> np.ndarray:
    """An Open3D tensor (it has .numpy()), or anything numpy takes."""
    return np.asarray(x.numpy() if hasattr(x, "numpy") else x)


def _mesh_arrays(mesh: Any):
    if hasattr(mesh, "vertex") and hasattr(mesh, "triangle"):  # o3d.t.geometry.TriangleMesh
        return _array(mesh.vertex.positions), _array(mesh.triangle.indices)
    if hasattr(mesh, "vertices") and hasattr(mesh, "triangles"):  # legacy TriangleMesh
        return _array(mesh.vertices), _array(mesh.triangles)
    raise InvalidArgumentError("add_triangles: expected (vertices, indices) or a triangle mesh",
                               1)


class RaycastingScene:
    """Open3D's RaycastingScene on a treetrace structure ("rtree" unless
    told otherwise; any Accel name and options work).

    >>> import numpy as np, treetrace as tt
    >>> scene = tt.RaycastingScene()
    >>> scene.add_triangles(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),
    ...                     np.array([[0, 1, 2]], np.uint32))
    0
    >>> scene.add_triangles(np.array([[0, 0, 1], [1, 0, 1], [0, 1, 1]], np.float32),
    ...                     np.array([[0, 1, 2]], np.uint32))
    1
    >>> ans = scene.cast_rays(np.array([[0.2, 0.2, 3, 0, 0, -1]], np.float32))
    >>> ans["t_hit"].numpy(), ans["geometry_ids"].numpy(), ans["primitive_ids"].numpy()
    (array([2.], dtype=float32), array([1], dtype=uint32), array([0], dtype=uint32))
    """

    INVALID_ID = INVALID_ID

    def __init__(self, accel: str = "rtree", context: Optional[Context] = None,
                 **options: Any) -> None:
        self._kind, self._options, self._context = accel, options, context
        self._vertices: List[np.ndarray] = []
        self._indices: List[np.ndarray] = []
        self._accel: Optional[Accel] = None
        self._first: np.ndarray = np.zeros(0, np.int64)  # each geometry's first triangle

    def add_triangles(self, vertex_positions: Any, triangle_indices: Any = None) -> int:
        """Adds a mesh; returns its geometry id (0, 1, ...).

        >>> import treetrace as tt
        >>> tt.RaycastingScene().add_triangles([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        0
        """
        if triangle_indices is None:
            v, i = _mesh_arrays(vertex_positions)
        else:
            v, i = _array(vertex_positions), _array(triangle_indices)
        v = np.asarray(v, np.float32).reshape(-1, 3)
        i = np.asarray(i).reshape(-1, 3)
        if i.size and (i.min() < 0 or i.max() >= len(v)):
            raise InvalidArgumentError("add_triangles: an index is outside 0 .. %d" % (len(v) - 1),
                                       1)
        self._vertices.append(v)
        self._indices.append(i.astype(np.int64))
        self._accel = None  # rebuilt on the next query
        return len(self._vertices) - 1

    def _structure(self) -> Accel:
        if self._accel is None:
            offsets = np.cumsum([0] + [len(v) for v in self._vertices])
            v = np.concatenate(self._vertices) if self._vertices else np.zeros((0, 3), np.float32)
            i = (np.concatenate([ix + off for ix, off in zip(self._indices, offsets)])
                 if self._indices else np.zeros((0, 3), np.int64))
            self._first = np.cumsum([0] + [len(ix) for ix in self._indices])[:-1]
            self._accel = Accel(Scene.from_arrays(v, i.astype(np.uint32), context=self._context),
                                self._kind, **self._options)
        return self._accel

    def cast_rays(self, rays: Any, nthreads: int = 0) -> Dict[str, np.ndarray]:
        """Closest hits of (..., 6) rays, keys as Open3D's. nthreads must be 0:
        threads come from the Context (tt.Context(threads=N)).

        >>> import treetrace as tt
        >>> s = tt.RaycastingScene()
        >>> _ = s.add_triangles([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> sorted(s.cast_rays([[0.2, 0.2, 1, 0, 0, -1]]))
        ['geometry_ids', 'primitive_ids', 'primitive_normals', 'primitive_uvs', 't_hit']
        """
        self._threads(nthreads)
        ans = self._structure().cast_rays(_array(rays))
        prim = np.asarray(ans["primitive_ids"])
        hit = prim != INVALID_ID
        geometry = np.full(prim.shape, INVALID_ID, np.uint32)
        local = prim.copy()
        if hit.any():
            g = np.searchsorted(self._first, prim[hit], side="right") - 1
            geometry[hit] = g
            local[hit] = prim[hit] - self._first[g]
        ans["geometry_ids"] = geometry.view(type(ans["t_hit"]))
        ans["primitive_ids"] = local.view(type(ans["t_hit"]))
        return ans

    def test_occlusions(self, rays: Any, tnear: float = 0.0, tfar: float = float("inf"),
                        nthreads: int = 0) -> np.ndarray:
        """Whether anything lies on [tnear, tfar) of each ray.

        >>> import treetrace as tt
        >>> s = tt.RaycastingScene()
        >>> _ = s.add_triangles([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> s.test_occlusions([[0.2, 0.2, 1, 0, 0, -1]], tfar=0.5)
        array([False])
        """
        self._threads(nthreads)
        return self._structure().test_occlusions(_array(rays), tnear, tfar)

    @staticmethod
    def _threads(nthreads: int) -> None:
        if nthreads:
            raise InvalidArgumentError("nthreads: treetrace takes its threads from the Context "
                                       "(tt.RaycastingScene(context=tt.Context(threads=N)))", 1)


__all__ = ["RaycastingScene"]
