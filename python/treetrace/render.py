"""Cameras, primary rays of a view, rendering to arrays and PNG files."""

from __future__ import annotations

import ctypes
from typing import Optional, Tuple

import numpy as np

from . import _lib
from ._util import check, address, lib
from .core import default_context


class Camera:
    """A pinhole camera per the conventions (vertical fov in degrees) with
    an optional point light: Camera(eye, look, up=(0, 1, 0), fov=45,
    light=None), Camera.from_view(views_tsv, "scene:view") or
    Camera.frame(scene).

    >>> import treetrace as tt
    >>> cam = tt.Camera(eye=(0, 0, 5), look=(0, 0, 0), fov=60)
    >>> cam.eye, cam.fov
    (array([0., 0., 5.], dtype=float32), 60.0)
    """

    def __init__(self, eye, look, up=(0.0, 1.0, 0.0), fov: float = 45.0, light=None) -> None:
        c = _lib.Camera()
        c.eye[:] = [float(x) for x in eye]
        c.look[:] = [float(x) for x in look]
        c.up[:] = [float(x) for x in up]
        c.fov_deg = float(fov)
        if light is not None:
            c.light[:] = [float(x) for x in light]
            c.has_light = 1
        self._c = c

    @classmethod
    def _wrap(cls, c):
        cam = cls.__new__(cls)
        cam._c = c
        return cam

    @classmethod
    def from_view(cls, views_path, name: str, context=None) -> "Camera":
        """The view "scene:view" of a views.tsv file (see the scenes' README).

        >>> import treetrace as tt
        >>> tt.Camera.from_view("no/views.tsv", "bunny:main")
        Traceback (most recent call last):
          ...
        treetrace.errors.FileError: no/views.tsv: cannot open: No such file or directory
        """
        ctx = context or default_context()
        c = _lib.Camera()
        check(lib.tt_view_find(ctx._h, str(views_path).encode(), name.encode(), ctypes.byref(c)),
              ctx._h)
        return cls._wrap(c)

    @classmethod
    def frame(cls, scene) -> "Camera":
        """A camera framing the scene's box, with a light above-left of the eye.

        >>> import treetrace as tt
        >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> tt.Camera.frame(s).light is not None
        True
        """
        c = _lib.Camera()
        lib.tt_camera_frame_scene(scene._h, ctypes.byref(c))
        return cls._wrap(c)

    eye = property(lambda self: np.array(self._c.eye[:], np.float32))
    look = property(lambda self: np.array(self._c.look[:], np.float32))
    up = property(lambda self: np.array(self._c.up[:], np.float32))
    fov = property(lambda self: self._c.fov_deg)
    light = property(lambda self: np.array(self._c.light[:], np.float32)
                     if self._c.has_light else None)

    def rays(self, width: int, height: int
             ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The primary rays tt_render traces, row-major from the top-left:
        (origins, directions, tmin, tmax) as views of one (H*W, 8) float32
        array in tt_ray's layout (no copy when passed to the batch calls).

        >>> import treetrace as tt
        >>> org, d, tmin, tmax = tt.Camera((0, 0, 5), (0, 0, 0)).rays(4, 3)
        >>> org.shape, d.shape, float(tmax[0])
        ((12, 3), (12, 3), inf)
        """
        buf = np.empty((int(width) * int(height), 8), np.float32)
        st = lib.tt_camera_rays(ctypes.byref(self._c), width, height, address(buf))
        if st != 0:
            check(st, None, "Camera.rays: a camera that cannot make rays, or a zero size")
        return buf[:, 0:3], buf[:, 4:7], buf[:, 3], buf[:, 7]


class RenderResult:
    """image: (H, W, 3) uint8 (shaded); summary: dict of tt_render_summary
    (timings, counts, Mrays/s); with hits=True also prim (H, W) uint32, t
    (H, W) float32 and shadow (H, W) bool, the conventions' hit buffer.

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> r = tt.render(s, tt.Accel(s), tt.Camera.frame(s), 8, 6, hits=True)
    >>> r.image.shape, r.prim.shape, r.summary["primary_rays"]
    ((6, 8, 3), (6, 8), 48)
    """

    def __init__(self, image, summary, prim=None, t=None, shadow=None):
        self.image, self.summary, self.prim, self.t, self.shadow = image, summary, prim, t, shadow


def _summary(s):
    out = {}
    for name, _ in s._fields_:
        value = getattr(s, name)
        if isinstance(value, _lib.RayStats):
            value = value.as_dict()
        elif isinstance(value, bytes):
            value = value.decode("utf-8", "replace")
        out[name] = value
    return out


def render(scene, accel, camera: Camera, width: int = 1024, height: int = 1024,
           shadows: bool = True, repeat: int = 1, hits: bool = False,
           image: bool = True) -> RenderResult:
    """tt_render on the context's threads: a shaded image as an array.

    >>> import treetrace as tt
    >>> s = tt.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> img = tt.render(s, tt.Accel(s, "kdtree"), tt.Camera.frame(s), 32, 24).image
    >>> img.shape, img.dtype
    ((24, 32, 3), dtype('uint8'))
    """
    ctx = scene.context
    o = _lib.RenderOptions()
    lib.tt_render_options_default(ctypes.byref(o))
    o.width, o.height = int(width), int(height)
    o.shadows = int(bool(shadows))
    o.repeat = int(repeat)
    o.keep_image = int(bool(image))
    o.keep_hits = int(bool(hits))
    res = ctypes.c_void_p()
    check(lib.tt_render(ctx._h, scene._h, accel._h, ctypes.byref(camera._c), ctypes.byref(o),
                        ctypes.byref(res)), ctx._h)
    try:
        summary = _summary(lib.tt_render_get_summary(res).contents)
        img = None
        if image:
            p = lib.tt_render_image(res)
            img = np.ctypeslib.as_array(ctypes.cast(p, ctypes.POINTER(ctypes.c_uint8)),
                                        shape=(o.height, o.width, 3)).copy()
        out = RenderResult(img, summary)
        if hits:
            size = ctypes.c_size_t()
            p = lib.tt_render_hits(res, ctypes.byref(size))
            raw = np.ctypeslib.as_array(ctypes.cast(p, ctypes.POINTER(ctypes.c_uint8)),
                                        shape=(size.value,)).copy()
            rec = raw.view(np.dtype([("prim", "<u4"), ("t", "<f4"), ("shadow", "<u4")]))
            out.prim = rec["prim"].reshape(o.height, o.width).copy()
            out.t = rec["t"].reshape(o.height, o.width).copy()
            out.shadow = rec["shadow"].reshape(o.height, o.width) != 0
        return out
    finally:
        lib.tt_render_result_destroy(res)


def write_png(path, image, context=None) -> None:
    """Writes an (H, W, 3) uint8 array as an 8-bit RGB PNG.

    >>> import numpy as np, treetrace as tt
    >>> tt.write_png("red.png", np.full((4, 4, 3), (255, 0, 0), np.uint8))
    >>> open("red.png", "rb").read(4)
    b'\\x89PNG'
    """
    ctx = context or default_context()
    img = np.ascontiguousarray(image, dtype=np.uint8)
    if img.ndim != 3 or img.shape[2] != 3:
        from .errors import InvalidArgumentError
        raise InvalidArgumentError("write_png: expected an (H, W, 3) array, got %s"
                                   % (img.shape,), 1)
    check(lib.tt_write_png(ctx._h, str(path).encode(), address(img), img.shape[1], img.shape[0]),
          ctx._h)
