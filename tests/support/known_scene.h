/* A tiny scene whose every pixel is known by construction, for end-to-end
 * tests of the renderer and the CLI:
 *
 *   camera at the origin looking down -z, fov 90, 16x12 pixels (h = 1,
 *   a = 4/3); a square quad in z = -2 over x in [-3, 0], y in [-3, 3] (prims
 *   0 and 1, split along the diagonal y = 2x + 3), covering exactly the left
 *   half of the image; a light at (-10, 0, -0.5); an occluder in z = -1.5
 *   over x in [-6, -3], y in [0, 5] (prims 2, 3), outside the view.
 *
 * A shadow ray from a quad point (x, y, -2) crosses z = -1.5 one third of the
 * way to the light, at ((2x - 10) / 3, 2y / 3): inside the occluder exactly
 * when y > 0, i.e. for the top six rows. */
#ifndef TT_TEST_KNOWN_SCENE_H
#define TT_TEST_KNOWN_SCENE_H

#include "treetrace/treetrace.h"

#define TT_KNOWN_W 16
#define TT_KNOWN_H 12
#define TT_KNOWN_VERTICES 8
#define TT_KNOWN_TRIANGLES 4
/* The CLI options that give the camera below. */
#define TT_KNOWN_CLI_CAMERA "--eye 0,0,0 --look 0,0,-1 --up 0,1,0 --fov 90 --light -10,0,-0.5"

extern const float tt_known_vertices[3 * TT_KNOWN_VERTICES];
extern const uint32_t tt_known_indices[3 * TT_KNOWN_TRIANGLES];

tt_camera tt_known_camera(void);

/* What pixel (x, y) must hold. prim is TT_INVALID_ID on a miss and
 * TT_KNOWN_EITHER where the pixel centre lies on the quad's diagonal. */
#define TT_KNOWN_EITHER 0xFFFFFFFEu
typedef struct tt_known_pixel {
    uint32_t prim;
    double t;
    uint32_t shadow;
} tt_known_pixel;
tt_known_pixel tt_known_expect(int x, int y, int with_shadows);

/* Compares a hit buffer with the construction byte by byte (little-endian,
 * the exact miss encoding); returns the number of bad pixels, printing the
 * first few under `what`. */
int tt_known_check_hits(const char *what, const uint8_t *hits, size_t size, int with_shadows);

/* Writes the scene as an ASCII PLY file; 0 on success. */
int tt_known_write_ply(const char *path);

#endif
