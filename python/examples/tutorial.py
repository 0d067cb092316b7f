"""treetrace tutorial: from a scene file to an ambient-occlusion image, in numpy.

Run it from the repository root (with the library built, see README.md):

    PYTHONPATH=python TREETRACE_LIBRARY=build/libtreetrace.so python3 python/examples/tutorial.py

It loads a scene, casts a camera's rays (Open3D's (N, 6) form), computes
ambient occlusion with numpy (random rays over each hit's hemisphere,
traced as one batch), shows depth, normals and occlusion with matplotlib,
and compares the speed of the acceleration structures on the same rays.
Headless (MPLBACKEND=Agg, as in CI) it writes the images to --out instead
of opening a window. Each step is a function, so the file reads top to
bottom like a notebook."""

import argparse
import os
import time

import numpy as np

import treetrace as tt

HERE = os.path.dirname(os.path.abspath(__file__))
BUNNY = os.path.join(HERE, "..", "..", "data", "bunny.ply")


# 1. A scene and a camera ---------------------------------------------------

def load(path):
    """The scene, and a camera framing it (Camera.from_view reads a views.tsv)."""
    scene = tt.Scene.load(path)
    print("%s: %d triangles, %d vertices" % (os.path.basename(path), scene.triangle_count,
                                            scene.vertex_count))
    vertices, indices = scene.arrays()  # the whole mesh as numpy arrays, one C call
    print("  vertex array %s %s, index array %s %s" % (vertices.shape, vertices.dtype,
                                                      indices.shape, indices.dtype))
    return scene, tt.Camera.frame(scene)


# 2. A camera's rays, cast in one call ---------------------------------------

def camera_rays(camera, width, height):
    """The camera's primary rays as one (H, W, 6) array: origin, direction."""
    org, d, _, _ = camera.rays(width, height)
    return np.concatenate([org, d], axis=1).reshape(height, width, 6)


def cast(accel, rays):
    """Closest hits, Open3D-style: t_hit, primitive_ids, _uvs, _normals."""
    ans = accel.cast_rays(rays)
    hit = ans["primitive_ids"] != tt.INVALID_ID
    print("  %d of %d rays hit" % (hit.sum(), hit.size))
    return ans, hit


# 3. Ambient occlusion with numpy ---------------------------------------------

def hemisphere(normals, samples, rng):
    """`samples` cosine-weighted directions around each normal: (N, S, 3)."""
    n = normals[:, None, :]
    # any vector not parallel to n, then an orthonormal frame (t, b, n)
    helper = np.where(np.abs(n[..., 0:1]) < 0.9, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    t = np.cross(helper, n)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(n, t)
    u1 = rng.random((len(normals), samples, 1))
    u2 = rng.random((len(normals), samples, 1))
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    return (r * np.cos(phi)) * t + (r * np.sin(phi)) * b + np.sqrt(1.0 - u1) * n


def ambient_occlusion(accel, rays, ans, hit, samples=16, radius=None, seed=1):
    """The fraction of each hit's hemisphere that is open within `radius`
    (default: a fifth of the scene's size): 1 open, 0 closed in."""
    lo, hi = accel.scene.bounds
    radius = radius or 0.2 * float(np.linalg.norm(hi - lo))
    flat = rays.reshape(-1, 6)
    h = hit.reshape(-1)
    t = ans["t_hit"].reshape(-1)[h].astype(np.float64)
    points = flat[h, 0:3] + t[:, None] * flat[h, 3:6]
    normals = ans["primitive_normals"].reshape(-1, 3)[h].astype(np.float64)
    # geometric normals face either way: turn them towards the camera
    flip = np.einsum("ij,ij->i", normals, flat[h, 3:6]) > 0
    normals[flip] *= -1
    dirs = hemisphere(normals, samples, np.random.default_rng(seed))
    eps = 1e-4 * radius
    origins = np.repeat(points + eps * normals, samples, axis=0)
    ao_rays = np.concatenate([origins, dirs.reshape(-1, 3)], axis=1).astype(np.float32)
    blocked = accel.test_occlusions(ao_rays, tfar=radius).reshape(-1, samples)
    image = np.full(hit.shape, np.nan)  # no surface, no occlusion: shown as background
    image.reshape(-1)[h] = 1.0 - blocked.mean(axis=1)
    return image, ao_rays, radius


# 4. Show the images with matplotlib ----------------------------------------

def show(ans, hit, ao, out_dir):
    import matplotlib.pyplot as plt

    depth = np.where(hit, ans["t_hit"], np.nan)
    normals = np.where(hit[..., None], 0.5 * (ans["primitive_normals"] + 1.0), 1.0)
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6))
    for ax, img, title, cmap in ((axes[0], depth, "depth t_hit", "viridis"),
                                 (axes[1], normals, "geometric normals", None),
                                 (axes[2], ao, "ambient occlusion", "gray")):
        ax.set_facecolor("#303030")  # the background (NaN pixels: no hit)
        im = ax.imshow(img, cmap=cmap)
        ax.set_title(title)
        ax.set_xticks([])
        ax.set_yticks([])
        if cmap:
            fig.colorbar(im, ax=ax, fraction=0.046)
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "tutorial-images.png")
    fig.savefig(path, dpi=120)
    print("  wrote %s" % path)
    if plt.get_backend().lower() != "agg":
        plt.show()
    plt.close(fig)
    return path


# 5. Compare the structures' speed -------------------------------------------

def compare(scene, rays, ao_rays, radius, out_dir, repeat=3):
    """Build time, and Mrays/s of the camera rays and of the AO rays, for each
    structure on the same rays (the best of `repeat` passes)."""
    import matplotlib.pyplot as plt

    configs = [("rtree", {}), ("kdtree", {"traversal": "htr"}),
               ("kdtree", {"traversal": "sltr"})]
    if "embree" in tt.accel_names():
        configs.append(("embree", {}))
    flat = rays.reshape(-1, 6)
    rows = []
    print("  %-14s %9s %15s %15s" % ("structure", "build [s]", "camera Mrays/s", "AO Mrays/s"))
    for name, opts in configs:
        accel = tt.Accel(scene, name, **opts)
        label = name + (" " + opts["traversal"] if "traversal" in opts else "")

        def best(fn):
            times = []
            for _ in range(repeat):
                t0 = time.perf_counter()
                fn()
                times.append(time.perf_counter() - t0)
            return min(times)

        tc = best(lambda: accel.cast_rays(flat))
        ta = best(lambda: accel.test_occlusions(ao_rays, tfar=radius))
        rows.append((label, accel.build_seconds, len(flat) / tc * 1e-6, len(ao_rays) / ta * 1e-6))
        print("  %-14s %9.3f %15.2f %15.2f" % rows[-1])
    fig, ax = plt.subplots(figsize=(6, 3.2))
    x = np.arange(len(rows))
    ax.bar(x - 0.2, [r[2] for r in rows], 0.4, label="camera rays (closest hit)",
           color="#0072B2")
    ax.bar(x + 0.2, [r[3] for r in rows], 0.4, label="AO rays (any hit)", color="#E69F00",
           hatch="//")
    ax.set_xticks(x)
    ax.set_xticklabels([r[0] for r in rows])
    ax.set_ylabel("Mrays/s (higher is faster)")
    ax.legend(frameon=False)
    fig.tight_layout()
    path = os.path.join(out_dir, "tutorial-speed.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print("  wrote %s" % path)
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scene", default=BUNNY, help="an OBJ or PLY file (default: data/bunny.ply)")
    p.add_argument("--size", default="320x240", help="image size WxH")
    p.add_argument("--samples", type=int, default=16, help="AO rays per pixel")
    p.add_argument("--out", default="tutorial-out", help="where the images go")
    a = p.parse_args(argv)
    width, height = (int(v) for v in a.size.split("x"))

    print("1. load")
    scene, camera = load(a.scene)
    print("2. cast the camera's rays")
    accel = tt.Accel(scene, "kdtree")
    rays = camera_rays(camera, width, height)
    ans, hit = cast(accel, rays)
    print("3. ambient occlusion (%d rays a pixel)" % a.samples)
    ao, ao_rays, radius = ambient_occlusion(accel, rays, ans, hit, a.samples)
    print("  mean openness of the hit pixels: %.3f" % np.nanmean(ao[hit]))
    print("4. show")
    show(ans, hit, ao, a.out)
    print("5. compare the structures")
    compare(scene, rays, ao_rays, radius, a.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
