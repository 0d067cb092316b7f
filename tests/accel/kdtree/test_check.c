/* tt_accel_check catches broken kd-trees: each corruption below is applied
 * to a correct tree, must be reported as TT_ERR_INVARIANT with a message
 * naming a node, and is then undone (the check passes again). */
#include <math.h>
#include <string.h>

#include "kd_testing.h"

static tt_context *ctx;
static tt_accel *acc;
static tt_kdtree *tree;

static void expect_broken(const char *what)
{
    tt_status st = tt_accel_check(acc);
    const char *msg = tt_context_last_error(ctx);
    CHECK_MSG(st == TT_ERR_INVARIANT && strstr(msg, "node") != NULL, "%s: status %d, message '%s'",
              what, (int)st, msg);
    if (st == TT_ERR_INVARIANT) printf("%s -> %s\n", what, msg);
}

/* The first leaf with at least n references, and the first interior node
 * that is (or is not) augmented below the root. */
static uint32_t find_leaf(uint32_t n)
{
    for (uint32_t i = 0; i < tree->node_slots; i++) {
        tt_kd_node x = tree->nodes[i];
        if (tt_kd_is_leaf(x.bits) && tt_kd_leaf_count(x.bits) >= n) return i;
    }
    return 0;
}

static uint32_t find_interior(int augmented)
{
    /* Walk the layout (extension slots are skipped via the aug flag). */
    for (uint32_t i = 0; i < tree->node_slots; i++) {
        tt_kd_node x = tree->nodes[i];
        if (i > 0 && !tt_kd_is_leaf(x.bits) && (int)tt_kd_is_aug(x.bits) == augmented) return i;
        if (!tt_kd_is_leaf(x.bits) && tt_kd_is_aug(x.bits)) i++;
    }
    return 0;
}

int main(void)
{
    ctx = tt_test_context();
    tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    acc = kd_build_with(ctx, scene, TT_KD_NLOGN, 3, TT_KD_HTR);
    tree = (tt_kdtree *)tt_kdtree_of(acc); /* the test corrupts it on purpose */
    REQUIRE_OK(ctx, tt_accel_check(acc));

    /* A leaf loses a triangle (replaced by one far away, order kept). */
    uint32_t leaf = find_leaf(2);
    uint32_t *ref = &tree->refs[tree->nodes[leaf].u.first];
    uint32_t saved[2] = {ref[0], ref[1]};
    uint32_t far = ref[0] > 500 ? 0 : (uint32_t)tt_scene_triangle_count(scene) - 1;
    if (far < ref[1]) ref[0] = far;
    else {
        ref[0] = ref[1];
        ref[1] = far;
    }
    expect_broken("leaf with a wrong triangle");
    ref[0] = saved[0];
    ref[1] = saved[1];
    CHECK_OK(ctx, tt_accel_check(acc));

    /* A leaf's reference count shrinks: a triangle goes missing. */
    tree->nodes[leaf].bits -= 1u << 3;
    expect_broken("leaf missing its last triangle");
    tree->nodes[leaf].bits += 1u << 3;
    CHECK_OK(ctx, tt_accel_check(acc));

    /* A split moves by one unit in the last place. */
    uint32_t inner = find_interior(0);
    float split = tree->nodes[inner].u.split;
    tree->nodes[inner].u.split = nextafterf(split, INFINITY);
    expect_broken("split moved by one ulp");
    tree->nodes[inner].u.split = split;
    CHECK_OK(ctx, tt_accel_check(acc));

    /* The augmentation: a flag where the d_min rule has none. */
    tree->nodes[inner].bits |= TT_KD_AUG_BIT;
    expect_broken("augmented flag against the d_min rule");
    tree->nodes[inner].bits &= ~TT_KD_AUG_BIT;
    CHECK_OK(ctx, tt_accel_check(acc));

    /* A sparse box that is not its node's cell, and a wrong parent link. */
    uint32_t aug_node = find_interior(1);
    tt_kd_aug *box = &tree->aug[tt_kd_aug_index(tree->nodes, aug_node)];
    float lo = box->lo[1];
    box->lo[1] = nextafterf(lo, -INFINITY);
    expect_broken("box one ulp larger than its cell");
    box->lo[1] = lo;
    uint32_t parent = box->parent;
    box->parent = parent == 0 ? TT_KD_NO_PARENT : 0;
    expect_broken("box linked to the wrong augmented ancestor");
    box->parent = parent;
    CHECK_OK(ctx, tt_accel_check(acc));

    /* A right child link pointing elsewhere. */
    uint32_t bits = tree->nodes[0].bits;
    tree->nodes[0].bits = (bits & 7u) | ((tt_kd_right(bits) + 1u) << 3);
    expect_broken("root's right child link off by one");
    tree->nodes[0].bits = bits;
    CHECK_OK(ctx, tt_accel_check(acc));

    tt_accel_destroy(acc);

    /* Without boxes below the root only triangle placement can tell that a
     * split moved: node 2 (the root's left child) moves half-way to its
     * cell's upper face, so triangles end up on the wrong side. */
    acc = kd_build_with(ctx, scene, TT_KD_NLOGN, -1, TT_KD_HTR);
    tree = (tt_kdtree *)tt_kdtree_of(acc);
    REQUIRE_OK(ctx, tt_accel_check(acc));
    kd_plane planes[2];
    float slo[3], shi[3];
    tt_scene_bounds(scene, slo, shi);
    REQUIRE_OK(ctx, kd_collect(tree, 0, slo, shi, planes, 0, 2) == 2 ? TT_OK : TT_ERR_INTERNAL);
    split = tree->nodes[2].u.split;
    CHECK(split == planes[1].pos);
    tree->nodes[2].u.split = 0.5f * (split + planes[1].hi[planes[1].axis]);
    expect_broken("split moved, no boxes to tell");
    tree->nodes[2].u.split = split;
    CHECK_OK(ctx, tt_accel_check(acc));
    /* One ulp towards the side of the triangles that ended exactly at the
     * plane (the candidate it came from) makes them straddle it: a child
     * lacks them. One of the two directions must be caught that way. */
    int lacks = 0;
    for (int dir = -1; dir <= 1; dir += 2) {
        tree->nodes[2].u.split = nextafterf(split, dir * INFINITY);
        if (tt_accel_check(acc) == TT_ERR_INVARIANT &&
            strstr(tt_context_last_error(ctx), "lacks triangle")) {
            printf("split moved one ulp -> %s\n", tt_context_last_error(ctx));
            lacks = 1;
        }
    }
    CHECK(lacks);
    tree->nodes[2].u.split = split;
    CHECK_OK(ctx, tt_accel_check(acc));
    tt_accel_destroy(acc);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
