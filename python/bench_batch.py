#!/usr/bin/env python3
"""The Python binding against the renderer on the same rays: the primary
rays of a view (1024 x 1024 = 1M by default) traced by tt_render's primary
pass and by Accel.intersect from numpy arrays, alternating, the minimum of
each over the rounds. The binding's time includes allocating the result
arrays; the hits are checked equal to the renderer's.

usage: bench_batch.py SCENE VIEWS SCENE:VIEW [ACCEL [THREADS [ROUNDS [SIZE]]]]"""
import sys
import time

import numpy as np

import treetrace as tt


def main(argv):
    if len(argv) < 4:
        print(__doc__)
        return 2
    scene_path, views, view = argv[1:4]
    accel_name = argv[4] if len(argv) > 4 else "kdtree"
    threads = int(argv[5]) if len(argv) > 5 else 2
    rounds = int(argv[6]) if len(argv) > 6 else 5
    size = int(argv[7]) if len(argv) > 7 else 1024
    ctx = tt.Context(threads=threads)
    scene = tt.Scene.load(scene_path, context=ctx)
    cam = tt.Camera.from_view(views, view, context=ctx)
    accel = tt.Accel(scene, accel_name)
    org, d, tmin, tmax = cam.rays(size, size)
    hint = accel.locate(cam.eye)
    best_render = best_py = best_py_rows = float("inf")
    for r in range(rounds):
        res = tt.render(scene, accel, cam, size, size, shadows=False, hits=(r == 0), image=False)
        best_render = min(best_render, res.summary["primary_s"])
        t0 = time.perf_counter()
        hits = accel.intersect(org, d, tmin, tmax, start_hint=hint, image_width=size)
        t1 = time.perf_counter()
        accel.intersect(org, d, tmin, tmax, start_hint=hint)
        t2 = time.perf_counter()
        best_py = min(best_py, t1 - t0)
        best_py_rows = min(best_py_rows, t2 - t1)
        if r == 0:
            same = (res.prim.ravel() == hits.prim).all() and (res.t.ravel() == hits.t).all()
            if not same:
                print("hits differ from the renderer's")
                return 1
    n = size * size
    print("accel: %s\nthreads: %d\nrays: %d\nrounds: %d" % (accel_name, threads, n, rounds))
    print("render_primary_mrays_per_s: %.3f" % (n / best_render * 1e-6))
    print("python_tiled_mrays_per_s: %.3f" % (n / best_py * 1e-6))
    print("python_rows_mrays_per_s: %.3f" % (n / best_py_rows * 1e-6))
    print("python_tiled_over_render: %.3f" % (best_render / best_py))
    print("python_rows_over_render: %.3f" % (best_render / best_py_rows))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
