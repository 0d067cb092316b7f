/* Every shared scene loads with the triangle and vertex counts and bounding
 * box of scenes.tsv, and spot-checked triangles match the file. The expected
 * triangles were extracted from the files by an independent script (Python's
 * struct and float parsing, fan triangulation), rounded to float. */
#include <math.h>

#include "core/context.h"
#include "io_util.h"

typedef struct spot {
    size_t index;
    float v[9];
} spot;

typedef struct expected {
    const char *file;
    size_t triangles, vertices;
    float lo[3], hi[3];
    spot spots[5];
} expected;

static const expected scenes[] = {
    {"bun_zipper.ply", 69451, 35947, {-0.0946899f, 0.0329874f, -0.0618736f}, {0.0610091f, 0.187321f, 0.0587997f},
     {{0, {-0.0923143998f, 0.132364005f, 0.0182221998f, -0.0921801999f, 0.132348001f, 0.0172237996f, -0.0927674025f, 0.130991995f, 0.0172310993f}},
      {1, {-0.0871677995f, 0.11039f, 0.0183619f, -0.0889611989f, 0.111860998f, 0.0183358993f, -0.0874425992f, 0.110454001f, 0.0173412003f}},
      {23150, {-0.0259693004f, 0.156663999f, -0.00260696001f, -0.0267733f, 0.156619996f, -0.00202229992f, -0.0270163007f, 0.155641004f, -0.00359794009f}},
      {34725, {-0.048787199f, 0.0545643009f, 0.0352206007f, -0.0481436998f, 0.0545921996f, 0.0360101983f, -0.0487686992f, 0.0559316985f, 0.0351683013f}},
      {69450, {-0.0668208972f, 0.0360359997f, 0.0339125991f, -0.0667060018f, 0.0375680998f, 0.0351922996f, -0.066733703f, 0.0374087989f, 0.0337221995f}}}},
    {"bun_zipper_res4.ply", 948, 453, {-0.0931466f, 0.0336204f, -0.056644f}, {0.0581591f, 0.181897f, 0.0578008f},
     {{0, {-0.0248607993f, 0.122913003f, 0.0245428998f, -0.0298756994f, 0.124251999f, 0.0209673997f, -0.0307197999f, 0.117989004f, 0.0306166001f}},
      {1, {-0.0698696002f, 0.168536007f, -0.0313319005f, -0.0771450996f, 0.167705998f, -0.0298797991f, -0.0702108964f, 0.165303007f, -0.0194661003f}},
      {316, {-0.0617959984f, 0.155741006f, -0.0207922999f, -0.0640821978f, 0.159391001f, -0.0169095993f, -0.0625087023f, 0.149933994f, -0.0150319003f}},
      {474, {-0.0824220031f, 0.0951121002f, 0.0310878009f, -0.0686864033f, 0.0923703983f, 0.0421978012f, -0.0818720981f, 0.107166f, 0.0310159996f}},
      {947, {-0.0352444984f, 0.0350571014f, 0.0178257003f, -0.0424620993f, 0.0343144014f, 0.00590597f, -0.0342325009f, 0.0337590016f, 0.00717516989f}}}},
    {"conference.ply", 331179, 194399, {-1020.13f, -2.7924f, -1055.66f}, {1685.81f, 650.293f, 668.489f},
     {{0, {-946.888f, 650.29303f, -930.630005f, -946.888f, 650.29303f, 525.664978f, -946.888f, -1.57216001f, -930.630005f}},
      {1, {-946.888f, 650.29303f, 525.664978f, -946.888f, -1.57216001f, 525.664978f, -946.888f, -1.57216001f, -930.630005f}},
      {110393, {1621.59998f, 0.407393992f, -995.36499f, 1621.59998f, 0.407393992f, -995.361023f, 1621.59998f, 0.412551999f, -995.359985f}},
      {165589, {1633.96997f, 0.506301999f, -1013.81f, 1633.96997f, 0.506301999f, -1013.79999f, 1633.96997f, 0.510941029f, -1013.79999f}},
      {331178, {1685.81006f, 13.9001999f, -1014.57001f, -951.874023f, 209.257996f, -1014.57001f, -951.874023f, 13.9001999f, -1014.57001f}}}},
    /* 18 quads: fans (v0, v1, v2), (v0, v2, v3) */
    {"cornell_box.obj", 36, 76, {0.0f, 0.0f, 0.0f}, {556.0f, 548.8f, 559.2f},
     {{0, {552.799988f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 559.200012f}},
      {1, {552.799988f, 0.0f, 0.0f, 0.0f, 0.0f, 559.200012f, 549.599976f, 0.0f, 559.200012f}},
      {12, {0.0f, 0.0f, 559.200012f, 0.0f, 0.0f, 0.0f, 0.0f, 548.799988f, 0.0f}},
      {18, {290.0f, 0.0f, 114.0f, 290.0f, 165.0f, 114.0f, 240.0f, 165.0f, 272.0f}},
      {35, {265.0f, 0.0f, 296.0f, 423.0f, 330.0f, 247.0f, 423.0f, 0.0f, 247.0f}}}},
    /* the last triangle is degenerate (two equal vertices) and must load */
    {"sibenik.obj", 75284, 40981, {-20.1411f, -15.3123f, -8.4968f}, {20.1411f, 15.3f, 8.4968f},
     {{0, {1.83894002f, -0.997300029f, -4.04320002f, 2.00510001f, -0.568527997f, -4.04320002f, 2.03114009f, -0.550677001f, -4.04320002f}},
      {1, {1.83894002f, -0.997300029f, -4.04320002f, 1.85894001f, -0.911695004f, -4.04320002f, 2.00510001f, -0.568527997f, -4.04320002f}},
      {25094, {-15.6056004f, -11.1800003f, -4.11367989f, -15.5707998f, -11.1499996f, -4.00769997f, -15.5425997f, -11.1800003f, -4.01940012f}},
      {37642, {11.3239002f, -12.2305002f, 3.36599994f, 11.2833996f, -12.2361002f, 3.38901997f, 11.2833996f, -12.2305002f, 3.36599994f}},
      {75283, {15.4489002f, -4.19124985f, 7.73907995f, 15.4489002f, -4.19124985f, 7.73907995f, 15.4489002f, -3.78790998f, 7.42959023f}}}},
};

static int close_rel(float a, float b)
{
    float scale = fmaxf(fabsf(a), fabsf(b));
    return fabsf(a - b) <= 1e-5f * scale;
}

/* Reads scenes.tsv and checks that the table above matches it, so that a
 * changed shared file cannot go unnoticed. */
static void check_against_tsv(void)
{
    FILE *f = fopen(tt_test_scene_path("scenes.tsv"), "r");
    CHECK(f != NULL);
    if (!f) return;
    char line[4096];
    int matched = 0;
    while (fgets(line, sizeof line, f)) {
        char name[64], file[128];
        size_t tris, verts;
        float lo[3], hi[3];
        if (sscanf(line, "%63[^\t]\t%127[^\t]\t%zu\t%zu\t%f,%f,%f\t%f,%f,%f", name, file, &tris, &verts,
                   &lo[0], &lo[1], &lo[2], &hi[0], &hi[1], &hi[2]) != 10)
            continue; /* the header */
        for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
            if (strcmp(scenes[i].file, file) != 0) continue;
            matched++;
            CHECK_MSG(scenes[i].triangles == tris && scenes[i].vertices == verts, "%s", file);
            for (int k = 0; k < 3; k++)
                CHECK_MSG(scenes[i].lo[k] == lo[k] && scenes[i].hi[k] == hi[k], "%s bbox", file);
        }
    }
    fclose(f);
    CHECK_MSG(matched == (int)(sizeof scenes / sizeof scenes[0]), "scenes.tsv lists %d of our scenes", matched);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    check_against_tsv();
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        const expected *e = &scenes[i];
        double t0 = tt_now();
        tt_scene *s = tt_test_load_scene(ctx, e->file);
        double t1 = tt_now();
        printf("%s: %zu triangles loaded in %.3f s\n", e->file, tt_scene_triangle_count(s), t1 - t0);
        CHECK_MSG(tt_scene_triangle_count(s) == e->triangles, "%s: %zu triangles", e->file,
                  tt_scene_triangle_count(s));
        CHECK_MSG(tt_scene_vertex_count(s) == e->vertices, "%s: %zu vertices", e->file,
                  tt_scene_vertex_count(s));
        float lo[3], hi[3];
        tt_scene_bounds(s, lo, hi);
        for (int k = 0; k < 3; k++)
            CHECK_MSG(close_rel(lo[k], e->lo[k]) && close_rel(hi[k], e->hi[k]),
                      "%s: bbox axis %d [%.9g, %.9g], expected [%.9g, %.9g]", e->file, k, lo[k], hi[k],
                      e->lo[k], e->hi[k]);
        for (int k = 0; k < 5; k++)
            CHECK_MSG(triangle_is(s, e->spots[k].index, e->spots[k].v), "%s: triangle %zu", e->file,
                      e->spots[k].index);
        tt_scene_destroy(s);
    }
    tt_context_destroy(ctx);
    return tt_test_finish();
}
