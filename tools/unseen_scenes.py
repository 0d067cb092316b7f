#!/usr/bin/python3
"""Scenes the project has never been tuned on, for issue 17's rule "judge a
lever by why it helps, not by one view".

The shared scenes are one scanned object (bunny), two architectural
interiors (sibenik, conference) and a box. Each scene here stresses what
those do not, with the density contrasts an R-tree's balance and a kd-tree's
SAH react to:
  atrium     a sponza-like hall: a few large walls and floor, colonnades of
             cylinders, and one dense sphere (about 200k small triangles)
             in the middle of mostly empty space;
  field      a tree in a field: a ground of a few huge triangles and a
             recursively branching tree of thin cylinders ending in many
             small leaf quads, all of it in one corner of the bounding box;
  terrain    a 256 x 256 heightfield with pillars standing on it: uniform
             density, long thin vertical boxes.
Deterministic (a fixed seed): the same files every run.

usage: tools/unseen_scenes.py OUT_DIR
writes OUT_DIR/{atrium,field,terrain}.ply (binary little-endian PLY) and
OUT_DIR/views.tsv in the shared scenes' format (../shared/scenes/README.md),
so raybench and treetrace take them as they take the shared ones
(tools/unseen_bench.sh runs raybench on every view).
"""
import math
import os
import sys

import numpy as np


class Mesh:
    def __init__(self):
        self.verts = []
        self.faces = []
        self.count = 0

    def add(self, v, f):
        v = np.asarray(v, dtype=np.float32).reshape(-1, 3)
        f = np.asarray(f, dtype=np.int64).reshape(-1, 3)
        self.verts.append(v)
        self.faces.append(f + self.count)
        self.count += len(v)

    def quad(self, a, b, c, d):
        self.add([a, b, c, d], [[0, 1, 2], [0, 2, 3]])

    def box(self, lo, hi):
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        p = [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
             [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]]
        f = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
             [3, 6, 2], [3, 7, 6], [0, 4, 7], [0, 7, 3], [1, 2, 6], [1, 6, 5]]
        self.add(p, f)

    def sphere(self, centre, radius, rings, segments):
        th = np.linspace(0.0, math.pi, rings + 1)
        ph = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
        t, p = np.meshgrid(th, ph, indexing="ij")
        v = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], -1)
        v = v.reshape(-1, 3) * radius + np.asarray(centre)
        r = np.arange(rings)[:, None]
        s = np.arange(segments)[None, :]
        a = r * segments + s
        b = r * segments + (s + 1) % segments
        c = a + segments
        d = b + segments
        f = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3),
                            np.stack([b, c, d], -1).reshape(-1, 3)])
        self.add(v, f)

    def cylinder(self, p0, p1, radius, segments):
        p0 = np.asarray(p0, dtype=np.float64)
        p1 = np.asarray(p1, dtype=np.float64)
        axis = p1 - p0
        n = axis / np.linalg.norm(axis)
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        u = np.cross(n, helper)
        u /= np.linalg.norm(u)
        w = np.cross(n, u)
        a = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
        ring = (np.cos(a)[:, None] * u + np.sin(a)[:, None] * w) * radius
        v = np.concatenate([p0 + ring, p1 + ring])
        s = np.arange(segments)
        t = (s + 1) % segments
        f = np.concatenate([np.stack([s, t, s + segments], -1),
                            np.stack([t, t + segments, s + segments], -1)])
        self.add(v, f)

    def arrays(self):
        return np.concatenate(self.verts), np.concatenate(self.faces)


def atrium(rng):
    m = Mesh()
    m.quad([-20, 0, -10], [20, 0, -10], [20, 0, 10], [-20, 0, 10])      # floor
    m.quad([-20, 15, -10], [-20, 15, 10], [20, 15, 10], [20, 15, -10])  # ceiling
    m.quad([-20, 0, -10], [-20, 15, -10], [20, 15, -10], [20, 0, -10])  # walls
    m.quad([-20, 0, 10], [20, 0, 10], [20, 15, 10], [-20, 15, 10])
    m.quad([-20, 0, -10], [-20, 0, 10], [-20, 15, 10], [-20, 15, -10])
    m.quad([20, 0, -10], [20, 15, -10], [20, 15, 10], [20, 0, 10])
    for x in np.linspace(-16, 16, 9):                                   # colonnades
        for z in (-6.0, 6.0):
            m.cylinder([x, 0, z], [x, 12, z], 0.6, 24)
            m.box([x - 0.9, 12, z - 0.9], [x + 0.9, 12.6, z + 0.9])
    m.sphere([0, 4, 0], 3.0, 320, 320)                                  # the dense object
    for _ in range(40):                                                 # scattered clutter
        c = rng.uniform([-18, 0, -9], [18, 0, 9])
        s = rng.uniform(0.2, 0.8, 3)
        m.box(c, c + s)
    return m, [("main", "-19,7,0", "0,4,0", "0,1,0", 60, "0,14,0"),
               ("close", "-6,5,-5", "0,4,0", "0,1,0", 50, "0,14,0")]


def field(rng):
    m = Mesh()
    m.quad([-500, 0, -500], [500, 0, -500], [500, 0, 500], [-500, 0, 500])

    def branch(p, d, length, radius, depth):
        q = p + d * length
        m.cylinder(p, q, radius, 8)
        if depth == 0:
            for _ in range(6):                                          # leaves
                c = q + rng.normal(0.0, 0.4, 3)
                e1 = rng.normal(0.0, 1.0, 3)
                e1 *= 0.15 / np.linalg.norm(e1)
                e2 = np.cross(e1, rng.normal(0.0, 1.0, 3))
                e2 *= 0.15 / np.linalg.norm(e2)
                m.quad(c - e1 - e2, c + e1 - e2, c + e1 + e2, c - e1 + e2)
            return
        for _ in range(3):
            nd = d + rng.normal(0.0, 0.6, 3)
            nd[1] = abs(nd[1]) + 0.2
            nd /= np.linalg.norm(nd)
            branch(q, nd, length * 0.72, radius * 0.65, depth - 1)

    branch(np.array([300.0, 0.0, 300.0]), np.array([0.0, 1.0, 0.0]), 6.0, 0.5, 8)
    return m, [("main", "280,6,280", "300,8,300", "0,1,0", 60, "250,80,320"),
               ("far", "200,20,200", "300,8,300", "0,1,0", 40, "250,80,320")]


def terrain(rng):
    m = Mesh()
    n = 256
    x = np.linspace(-100.0, 100.0, n)
    gx, gz = np.meshgrid(x, x, indexing="ij")
    h = 6.0 * np.sin(gx * 0.05) * np.cos(gz * 0.07) + rng.normal(0.0, 0.15, gx.shape)
    v = np.stack([gx, h, gz], -1).reshape(-1, 3)
    i = np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]
    f = np.concatenate([np.stack([i, i + 1, i + n], -1).reshape(-1, 3),
                        np.stack([i + 1, i + n + 1, i + n], -1).reshape(-1, 3)])
    m.add(v, f)
    for _ in range(300):
        c = rng.uniform(-95.0, 95.0, 2)
        w = rng.uniform(0.3, 1.2)
        m.box([c[0] - w, -8.0, c[1] - w], [c[0] + w, rng.uniform(8.0, 30.0), c[1] + w])
    return m, [("main", "-110,25,-110", "0,0,0", "0,1,0", 60, "50,120,-40"),
               ("low", "-60,6,0", "60,4,10", "0,1,0", 70, "50,120,-40")]


def write_ply(path, verts, faces):
    with open(path, "wb") as out:
        out.write(("ply\nformat binary_little_endian 1.0\n"
                   "comment tools/unseen_scenes.py\n"
                   f"element vertex {len(verts)}\n"
                   "property float x\nproperty float y\nproperty float z\n"
                   f"element face {len(faces)}\n"
                   "property list uchar int vertex_indices\nend_header\n").encode())
        out.write(np.ascontiguousarray(verts, dtype="<f4").tobytes())
        rec = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
        rec["n"] = 3
        rec["i"] = faces
        out.write(rec.tobytes())


def main():
    if len(sys.argv) != 2:
        sys.stderr.write(__doc__.split("\n\n")[-2] + "\n")
        return 2
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rows = ["scene\tview\teye\tlook\tup\tfov_deg\tlight"]
    for name, make in (("atrium", atrium), ("field", field), ("terrain", terrain)):
        mesh, views = make(np.random.default_rng(17))
        verts, faces = mesh.arrays()
        write_ply(os.path.join(out, name + ".ply"), verts, faces)
        print(f"{name}.ply: {len(faces)} triangles")
        for view, eye, look, up, fov, light in views:
            rows.append(f"{name}\t{view}\t{eye}\t{look}\t{up}\t{fov}\t{light}")
    with open(os.path.join(out, "views.tsv"), "w") as f:
        f.write("\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
