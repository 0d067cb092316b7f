"""Open3D-style ray casting: one (..., 6) ray array in, a dict of arrays out.

Accel inherits cast_rays and test_occlusions from RayCasting. Code written
for Open3D's RaycastingScene runs with one line changed through
treetrace.RaycastingScene (treetrace.o3d), or with the scene set up by
treetrace:

    Open3D                                     treetrace
    scene = o3d.t.geometry.RaycastingScene()   scene = tt.Scene.from_arrays(V, F)
    scene.add_triangles(V, F)                  accel = tt.Accel(scene, "kdtree")
    ans = scene.cast_rays(rays)                ans = accel.cast_rays(rays)
    occ = scene.test_occlusions(rays, tnear, tfar)  occ = accel.test_occlusions(rays, tnear, tfar)

    ans["t_hit"]             (...) float32, t of the closest hit in units of
                             the direction's length; inf on a miss
    ans["geometry_ids"]      (...) uint32, 0 (one mesh a scene); INVALID_ID on a miss
    ans["primitive_ids"]     (...) uint32, the triangle's index; INVALID_ID on a miss
    ans["primitive_uvs"]     (..., 2) float32, barycentrics (u, v) of vertices
                             1 and 2: p = (1-u-v) v0 + u v1 + v v2, as in
                             Open3D/Embree; (0, 0) on a miss
    ans["primitive_normals"] (..., 3) float32, unit normalize((v1-v0) x (v2-v0)),
                             Embree's orientation; (0, 0, 0) on a miss

The values are numpy arrays (with a .numpy() method, so Open3D code that
calls it keeps working). Threads come from the scene's Context, not from an
nthreads argument; count_intersections and list_intersections have no
counterpart (the structures stop at the closest hit)."""

from __future__ import annotations

from typing import Dict

import numpy as np

from .errors import InvalidArgumentError

_INVALID_ID = 0xFFFFFFFF


class _Result(np.ndarray):
    """A numpy array that also answers .numpy(), as an Open3D tensor does."""

    def numpy(self) -> np.ndarray:
        return np.asarray(self)

    def __repr__(self) -> str:
        return repr(np.asarray(self))


def _wrap(a: np.ndarray) -> np.ndarray:
    return a.view(_Result)


def _split_rays(rays):
    """(..., 6) rays -> origins and directions as (N, 3) float32 views (no
    copy for a float32 array with unit stride in its last axis), and the
    leading shape."""
    r = np.asarray(rays)
    if r.ndim < 1 or r.shape[-1] != 6:
        raise InvalidArgumentError("rays: expected shape (..., 6) (origin, direction), got %s"
                                   % (r.shape,), 1)
    if r.dtype != np.float32:
        r = r.astype(np.float32)
    lead = r.shape[:-1]
    flat = r.reshape(-1, 6)  # a view unless the leading axes cannot be merged
    return flat[:, 0:3], flat[:, 3:6], lead


class RayCasting:
    """cast_rays / test_occlusions on an Accel (mixed into treetrace.Accel)."""

    def cast_rays(self, rays) -> Dict[str, np.ndarray]:
        """The closest hit of each ray of a (..., 6) array (origin x, y, z,
        direction x, y, z) on [0, inf), as Open3D's RaycastingScene.cast_rays
        returns it: a dict with t_hit, geometry_ids, primitive_ids,
        primitive_uvs and primitive_normals, shaped like the rays' leading
        axes (see the module's docstring for each). The same hits as
        Accel.intersect.

        >>> import numpy as np, treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> a = tt.Accel(s, "kdtree")
        >>> ans = a.cast_rays([[0.25, 0.25, 2, 0, 0, -1], [2, 2, 2, 0, 0, -1]])
        >>> ans["t_hit"], ans["primitive_ids"]
        (array([ 2., inf], dtype=float32), array([         0, 4294967295], dtype=uint32))
        >>> ans["primitive_uvs"][0], ans["primitive_normals"][0]
        (array([0.25, 0.25], dtype=float32), array([0., 0., 1.], dtype=float32))
        """
        org, d, lead = _split_rays(rays)
        h = self.intersect(org, d, normals=True)
        miss = h.prim == _INVALID_ID
        uv = np.stack([h.u, h.v], axis=-1)
        uv[miss] = 0.0
        geometry = np.where(miss, np.uint32(_INVALID_ID), np.uint32(0)).astype(np.uint32)
        return {
            "t_hit": _wrap(h.t.reshape(lead)),
            "geometry_ids": _wrap(geometry.reshape(lead)),
            "primitive_ids": _wrap(h.prim.reshape(lead)),
            "primitive_uvs": _wrap(uv.reshape(lead + (2,))),
            "primitive_normals": _wrap(h.normal.reshape(lead + (3,))),
        }

    def test_occlusions(self, rays, tnear: float = 0.0,
                        tfar: float = float("inf")) -> np.ndarray:
        """Whether anything lies on [tnear, tfar) of each ray of a (..., 6)
        array: a bool array of the leading shape, as Open3D's
        RaycastingScene.test_occlusions. tnear/tfar: numbers or arrays of
        the leading shape.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> a = tt.Accel(s, "rtree")
        >>> a.test_occlusions([[0.25, 0.25, 2, 0, 0, -1]] * 2, tfar=[3.0, 1.0])
        array([ True, False])
        """
        org, d, lead = _split_rays(rays)
        n = org.shape[0]

        def per_ray(x, name):
            a = np.asarray(x, np.float32)
            if a.ndim == 0:
                return a
            if a.shape != lead:
                raise InvalidArgumentError("%s: expected a number or shape %s, got %s"
                                           % (name, lead, a.shape), 1)
            return a.reshape(n)

        occ = self.occluded(org, d, per_ray(tnear, "tnear"), per_ray(tfar, "tfar"))
        return _wrap(occ.reshape(lead))


__all__ = ["RayCasting"]
