/* Robustness: thousands of randomly damaged copies of small valid OBJ, ascii
 * PLY, binary PLY and views files (bytes flipped, inserted, deleted, the file
 * cut short). Every load must return either TT_OK with a sane scene or
 * TT_ERR_PARSE with a message naming the file; never crash, leak (the suite
 * runs under ASan) or touch memory outside the buffer (each input is copied
 * into an exactly-sized allocation). */
#include <math.h>

#include "io_util.h"

static uint32_t rng = 2463534242u;
static uint32_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

static buf make_binary_ply(int big_endian)
{
    buf b = {0};
    buf_printf(&b, "ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                   "property float z\nproperty list uchar short n\nelement face 2\n"
                   "property list uchar uint vertex_indices\nend_header\n",
               big_endian ? "binary_big_endian" : "binary_little_endian");
    for (int i = 0; i < 4; i++) {
        float v[3] = {(float)(i & 1), (float)(i >> 1), 0.5f};
        for (int k = 0; k < 3; k++) {
            unsigned char bytes[4];
            uint32_t u;
            memcpy(&u, &v[k], 4);
            for (int j = 0; j < 4; j++) bytes[j] = (unsigned char)(u >> (8 * (big_endian ? 3 - j : j)));
            buf_put(&b, bytes, 4);
        }
        unsigned char list[5] = {2, 0, 1, 0, 2};
        buf_put(&b, list, 5);
    }
    for (int f = 0; f < 2; f++) {
        unsigned char c = 3;
        buf_put(&b, &c, 1);
        for (int k = 0; k < 3; k++) {
            uint32_t idx = (uint32_t)(f + k);
            unsigned char bytes[4];
            for (int j = 0; j < 4; j++) bytes[j] = (unsigned char)(idx >> (8 * (big_endian ? 3 - j : j)));
            buf_put(&b, bytes, 4);
        }
    }
    return b;
}

static void mutate(const buf *src, buf *dst)
{
    dst->size = 0;
    buf_put(dst, src->data, src->size);
    int edits = 1 + (int)(next() % 4);
    for (int e = 0; e < edits && dst->size > 0; e++) {
        size_t at = next() % dst->size;
        static const char interesting[] = " \n\t/-+.e0123456789\r\xff\x80";
        switch (next() % 6) {
        case 0: dst->data[at] = (char)next(); break;
        case 1: dst->data[at] = interesting[next() % (sizeof interesting - 1)]; break;
        case 2: dst->data[at] ^= (char)(1u << (next() % 8)); break;
        case 3: /* delete */
            memmove(dst->data + at, dst->data + at + 1, dst->size - at - 1);
            dst->size--;
            break;
        case 4: { /* insert */
            char c = interesting[next() % (sizeof interesting - 1)];
            buf_put(dst, "", 1);
            memmove(dst->data + at + 1, dst->data + at, dst->size - at - 1);
            dst->data[at] = c;
            break;
        }
        case 5: dst->size = at; break; /* cut short */
        }
    }
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    buf inputs[5] = {{0}};
    buf_printf(&inputs[0], "# obj\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 -1.5e-1\nvn 0 0 1\nf 1/1/1 2//1 3 4\nf -1 -2 -3\n");
    buf_printf(&inputs[1], "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                           "property float z\nproperty uchar c\nelement face 2\nproperty list uchar int vertex_indices\n"
                           "end_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 .5 4\n3 0 1 2\n4 0 1 2 3\n");
    inputs[2] = make_binary_ply(0);
    inputs[3] = make_binary_ply(1);
    buf_printf(&inputs[4], "scene\tview\teye\tlook\tup\tfov_deg\tlight\na\tv\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,3\n"
                           "a\tw\t1,0,5\t0,0,0\t0,1,0\t45\t\n");
    long ok = 0, refused = 0, bad = 0;
    buf m = {0};
    for (int iter = 0; iter < 100000; iter++) {
        int which = iter % 5;
        mutate(&inputs[which], &m);
        char *exact = malloc(m.size ? m.size : 1);
        memcpy(exact, m.data, m.size);
        tt_status st;
        if (which < 4) {
            tt_scene *s = NULL;
            st = tt_scene_load_memory(ctx, "mut", NULL, exact, m.size, &s);
            if (st == TT_OK) {
                size_t n = tt_scene_triangle_count(s);
                float lo[3], hi[3];
                tt_scene_bounds(s, lo, hi);
                int sane = n > 0 && s != NULL;
                for (int k = 0; k < 3; k++) sane = sane && isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k];
                if (!sane && bad++ < 5) fprintf(stderr, "iteration %d: an insane scene\n", iter);
                tt_scene_destroy(s);
            } else if (s != NULL && bad++ < 5) {
                fprintf(stderr, "iteration %d: a scene returned with an error\n", iter);
            }
        } else {
            tt_camera c;
            st = tt_view_find_memory(ctx, "mut", exact, m.size, "a:v", &c);
            if (st == TT_OK && !(c.fov_deg > 0 && c.fov_deg < 180) && bad++ < 5)
                fprintf(stderr, "iteration %d: fov %g accepted\n", iter, c.fov_deg);
        }
        free(exact);
        if (st == TT_OK) ok++;
        else if (st == TT_ERR_PARSE && strncmp(tt_context_last_error(ctx), "mut", 3) == 0) refused++;
        else if (bad++ < 5)
            fprintf(stderr, "iteration %d: %s: %s\n", iter, tt_strerror(st), tt_context_last_error(ctx));
    }
    printf("%ld loaded, %ld refused\n", ok, refused);
    CHECK_MSG(bad == 0, "%ld bad outcomes", bad);
    CHECK(ok > 1000 && refused > 1000); /* both outcomes were exercised */
    for (int i = 0; i < 5; i++) free(inputs[i].data);
    free(m.data);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
