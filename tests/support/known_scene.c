#include "known_scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

const float tt_known_vertices[3 * TT_KNOWN_VERTICES] = {
    -3, -3, -2,    0, -3, -2,    0, 3, -2,    -3, 3, -2,    /* the quad     */
    -6, 0, -1.5f,  -3, 0, -1.5f, -3, 5, -1.5f, -6, 5, -1.5f, /* the occluder */
};
const uint32_t tt_known_indices[3 * TT_KNOWN_TRIANGLES] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};

tt_camera tt_known_camera(void)
{
    tt_camera c;
    memset(&c, 0, sizeof c);
    c.look[2] = -1.0f;
    c.up[1] = 1.0f;
    c.fov_deg = 90.0f;
    c.light[0] = -10.0f;
    c.light[2] = -0.5f;
    c.has_light = 1;
    return c;
}

tt_known_pixel tt_known_expect(int x, int y, int with_shadows)
{
    tt_known_pixel e;
    const int W = TT_KNOWN_W, H = TT_KNOWN_H;
    double u = (2.0 * (x + 0.5) / W - 1.0) * (double)W / H, v = 1.0 - 2.0 * (y + 0.5) / H;
    if (u >= 0) {
        e.prim = TT_INVALID_ID;
        e.t = INFINITY;
        e.shadow = 0;
        return e;
    }
    double px = 2 * u, py = 2 * v; /* the hit point on z = -2 */
    double side = py - (2 * px + 3);
    e.prim = fabs(side) < 1e-3 ? TT_KNOWN_EITHER : (side < 0 ? 0u : 1u);
    e.t = 2.0 * sqrt(u * u + v * v + 1.0);
    e.shadow = with_shadows && py > 0;
    return e;
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

int tt_known_check_hits(const char *what, const uint8_t *hits, size_t size, int with_shadows)
{
    const int W = TT_KNOWN_W, H = TT_KNOWN_H;
    if (!hits || size != (size_t)W * H * 12) {
        fprintf(stderr, "%s: hit buffer of %zu bytes, expected %d\n", what, hits ? size : 0,
                W * H * 12);
        return W * H;
    }
    int bad = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            const uint8_t *p = hits + 12 * ((size_t)y * W + x);
            tt_known_pixel e = tt_known_expect(x, y, with_shadows);
            uint32_t prim = get_u32(p), tbits = get_u32(p + 4), shadow = get_u32(p + 8);
            float t;
            memcpy(&t, &tbits, sizeof t);
            int ok;
            if (e.prim == TT_INVALID_ID) {
                /* 0xFFFFFFFF, +inf (0x7F800000), 0, all little-endian */
                static const uint8_t miss[12] = {0xff, 0xff, 0xff, 0xff, 0x00, 0x00,
                                                 0x80, 0x7f, 0,    0,    0,    0};
                ok = memcmp(p, miss, 12) == 0;
            } else {
                ok = (e.prim == TT_KNOWN_EITHER ? prim <= 1 : prim == e.prim) &&
                     fabs(t - e.t) <= 1e-5 * e.t && shadow == e.shadow;
            }
            if (!ok && bad++ < 5)
                fprintf(stderr, "%s: pixel %d,%d: prim %u t %.9g shadow %u, expected %u %.9g %u\n",
                        what, x, y, prim, t, shadow, e.prim, e.t, e.shadow);
        }
    }
    return bad;
}

int tt_known_write_ply(const char *path)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
                "end_header\n",
            TT_KNOWN_VERTICES, TT_KNOWN_TRIANGLES);
    for (int i = 0; i < TT_KNOWN_VERTICES; i++)
        fprintf(fp, "%.9g %.9g %.9g\n", tt_known_vertices[3 * i], tt_known_vertices[3 * i + 1],
                tt_known_vertices[3 * i + 2]);
    for (int i = 0; i < TT_KNOWN_TRIANGLES; i++)
        fprintf(fp, "3 %u %u %u\n", tt_known_indices[3 * i], tt_known_indices[3 * i + 1],
                tt_known_indices[3 * i + 2]);
    return fclose(fp) == 0 ? 0 : -1;
}
