"""Status checking and numpy <-> pointer plumbing shared by the modules."""

import ctypes

import numpy as np

from . import _lib
from .errors import error_for, InvalidArgumentError

lib = _lib.lib


def check(status, ctx_handle, what=""):
    """Raises the status's exception with the context's last message."""
    if status == 0:
        return
    message = ""
    if ctx_handle:
        message = (lib.tt_context_last_error(ctx_handle) or b"").decode("utf-8", "replace")
    name = (lib.tt_strerror(status) or b"").decode()
    if not message:
        message = "%s%s" % (what + ": " if what else "", name)
    raise error_for(status, message, name)


def address(array):
    return array.__array_interface__["data"][0]


def as_float32(x, name):
    """x as a float32 array; no copy when it already is one (any strides)."""
    a = np.asarray(x)
    if a.dtype != np.float32:
        a = a.astype(np.float32)
    return a


def vectors(x, n, name):
    """A float32 (n, 3) array or one (3,) vector for all rays: returns
    (array, pointers to x, y, z of ray 0, byte stride between rays)."""
    a = as_float32(x, name)
    if a.ndim == 1:
        if a.shape != (3,):
            raise InvalidArgumentError("%s: expected shape (3,) or (N, 3), got %s" % (name, a.shape))
        stride = 0
        comp = a.strides[0]
    elif a.ndim == 2 and a.shape[1] == 3:
        if a.shape[0] != n:
            raise InvalidArgumentError("%s: %d rows, expected %d" % (name, a.shape[0], n))
        stride, comp = a.strides
    else:
        raise InvalidArgumentError("%s: expected shape (3,) or (N, 3), got %s" % (name, a.shape))
    base = address(a)
    return a, [base + k * comp for k in range(3)], stride


def scalars(x, n, name):
    """None, a number or an (n,) array: (array or None, pointer, stride)."""
    if x is None:
        return None, None, 0
    a = as_float32(x, name)
    if a.ndim == 0:
        a = a.reshape(1)
        return a, address(a), 0
    if a.shape != (n,):
        raise InvalidArgumentError("%s: expected a number or shape (%d,), got %s" % (name, n, a.shape))
    return a, address(a), a.strides[0]


def ray_count(origins, directions):
    for x in (directions, origins):
        a = np.asarray(x)
        if a.ndim == 2:
            return a.shape[0]
    return 1
