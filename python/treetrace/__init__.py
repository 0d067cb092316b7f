"""treetrace: ray tracing triangle scenes through R-trees and kd-trees with
sparse boxes, from Python, over the C library libtreetrace.so.

    import numpy as np, treetrace as tt
    scene = tt.Scene.load("data/bunny.ply")
    accel = tt.Accel(scene, "kdtree", traversal="htr")
    hits = accel.intersect(origins, directions)   # (N, 3) float32 arrays
    hits.t, hits.u, hits.v, hits.prim             # (N,) arrays

Batches run on the context's threads (tt.Context(threads=N), passed to
Scene.load/from_arrays). Errors raise treetrace.Error subclasses carrying
the library's message. The library is found through TREETRACE_LIBRARY, next
to this package, or where it was installed (see README.md)."""

from ._lib import lib as _clib
from .core import (INVALID_ID, Accel, Context, Hits, Scene, accel_names, default_context,
                   isa_best, isa_supported, version)
from .errors import (Error, FileError, InternalError, InvalidArgumentError, InvariantError,
                     NoDeviceError, OutOfMemoryError, ParseError, UnsupportedError)
from .render import Camera, RenderResult, render, write_png
# dynamic scenes: Scene edits, Accel.update (a module of its own)
from .dynamic import BusyError, StaleError

library_path = _clib.path
__version__ = version()

__all__ = ["INVALID_ID", "Accel", "Camera", "Context", "Error", "FileError", "Hits",
           "InternalError", "InvalidArgumentError", "InvariantError", "NoDeviceError",
           "OutOfMemoryError", "ParseError", "RenderResult", "Scene", "UnsupportedError",
           "accel_names", "default_context", "isa_best", "isa_supported", "library_path",
           "render", "version", "write_png", "BusyError", "StaleError"]

# Open3D's RaycastingScene interface (cast_rays / test_occlusions on (..., 6)
# rays: treetrace.raycast, treetrace.o3d).
from .o3d import RaycastingScene  # noqa: E402

__all__ += ["RaycastingScene"]
