/* A shadow packet's cone (rtc_packet.h, occlusion walk with widened rows):
 * four planes around all the packet's segments, used at each node as a
 * cull beside the interval test, never instead of the per-ray tests.
 *
 * Why: shadow rays of a run run from hit points spread along a row of the
 * image to one point light. The interval test bounds their origins and
 * reciprocals separately, so a child anywhere in the box of the origins
 * passes it; on Sibenik 8.7 of 16 children passed a node where 4.6 were
 * hit by some ray (rpkshadow note), and the per-(child, group) tests of
 * the others were the walk's largest item. The segments from a row of
 * origins to one end point fill a thin wedge with its apex at the light;
 * planes through the apex bound it far more tightly than any box.
 *
 * Exactness: the cone only drops a child when no ray's own test could keep
 * it. If ray i's widened test (pk_child_occ_wide) keeps a box, the point
 * o + t d at its computed entry t (tmin <= t <= (tcf + pad)(1 + u)) lies
 * in the box grown on axis j by 2^-19 (|lo_j - o_j| + |hi_j - o_j|)
 * + pad |d_j| (1 + 2^-10) (the rounding of the slab distances, the
 * 2^-20 widening, the pad). So the box grown by E = 2^-17 Mc + 1.01
 * max_i pad_i |d_i| (Mc bounds every coordinate: origins, far ends, the
 * root's boxes, which hold every box below them) meets the segment
 * [o, o + T d], T = (tcf + pad)(1 + 2^-16). A plane n x <= h with h the
 * largest n x over all segment ends holds every segment; the box is kept
 * when its lowest n x, less |n|_1 E and the float sums' rounding (again
 * bounded through Mc), is at most h. The plane normals need no care: h is
 * computed from the ends whatever they are. */
#ifndef RTC_PACKET_CONE_H
#define RTC_PACKET_CONE_H

TT_RT_INLINE float pk_dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

TT_RT_INLINE void pk_cross3(const float a[3], const float b[3], float c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Sets P->cone (0: no cull) and, when 1, the planes cn[p] x <= ch[p]. Needs
 * pk_widen's tcf and rtc_pk_load's rows. */
TT_RT_INLINE void pk_cone(pk_rays *P, const tt_rtc *t)
{
    P->cone = 0;
    const uint32_t last = P->n - 1;
    const float T0 = (P->tcf[0] + P->pad[0]) * (1.0f + 0x1p-16f);
    const float o0[3] = {P->ox[0], P->oy[0], P->oz[0]};
    const float o1[3] = {P->ox[last], P->oy[last], P->oz[last]};
    const float A[3] = {o0[0] + T0 * P->d[0][0], o0[1] + T0 * P->d[1][0],
                        o0[2] + T0 * P->d[2][0]};
    /* the axis from the origins' middle to the apex, U across the run of
     * origins, V across both */
    float D[3], s[3], U[3], V[3];
    for (int k = 0; k < 3; k++) {
        D[k] = A[k] - 0.5f * (o0[k] + o1[k]);
        s[k] = o1[k] - o0[k];
    }
    const float dd = pk_dot3(D, D);
    if (!(dd > 0x1p-100f && dd < 0x1p100f)) return;
    const float sd = pk_dot3(s, D) / dd;
    for (int k = 0; k < 3; k++) U[k] = s[k] - sd * D[k];
    float uu = pk_dot3(U, U);
    if (!(uu > dd * 0x1p-30f && uu < 0x1p100f)) {
        const float ax = fabsf(D[0]), ay = fabsf(D[1]), az = fabsf(D[2]);
        const float e[3] = {ax <= ay && ax <= az, !(ax <= ay && ax <= az) && ay <= az,
                            !(ax <= ay && ax <= az) && !(ay <= az)};
        pk_cross3(D, e, U);
        uu = pk_dot3(U, U);
        if (!(uu > 0x1p-100f)) return;
    }
    pk_cross3(D, U, V);
    const float vv = pk_dot3(V, V);
    if (!(vv > 0x1p-100f && vv < 0x1p100f)) return;
    /* the planes: through the apex along V, one by each end of the run of
     * origins (its extremes across U, image rows being runs), and the
     * slab of the origins and the apex across V; U's, V's lengths need
     * no care (the margin scales with |n|_1) */
    {
        const float e0[3] = {o0[0] - A[0], o0[1] - A[1], o0[2] - A[2]};
        const float e1[3] = {o1[0] - A[0], o1[1] - A[1], o1[2] - A[2]};
        const float sV = 1.0f / sqrtf(vv);
        for (int k = 0; k < 3; k++) V[k] *= sV;
        pk_cross3(e1, V, P->cn[0]);
        pk_cross3(V, e0, P->cn[1]);
        for (int k = 0; k < 3; k++) {
            P->cn[2][k] = V[k];
            P->cn[3][k] = -V[k];
        }
    }
    /* one pass: h, the largest n x over the segment ends, and the bounds
     * of the coordinates and pads */
    const pk_v zero = PK_SET1(0.0f), ninf = PK_SET1(-TT_INF), inf = PK_SET1(TT_INF);
    const pk_v grow = PK_SET1(1.0f + 0x1p-16f);
    pk_v h0 = ninf, h1 = ninf, vmax = ninf, vmin = inf, mc = zero, pdm = zero;
    const pk_v n0x = PK_SET1(P->cn[0][0]), n0y = PK_SET1(P->cn[0][1]), n0z = PK_SET1(P->cn[0][2]);
    const pk_v n1x = PK_SET1(P->cn[1][0]), n1y = PK_SET1(P->cn[1][1]), n1z = PK_SET1(P->cn[1][2]);
    const pk_v vx = PK_SET1(V[0]), vy = PK_SET1(V[1]), vz = PK_SET1(V[2]);
    for (uint32_t o = 0; o < P->groups * PK_L; o += PK_L) {
        const pk_v ox = PK_LOAD(P->ox + o), oy = PK_LOAD(P->oy + o), oz = PK_LOAD(P->oz + o);
        const pk_v dx = PK_LOAD(P->d[0] + o), dy = PK_LOAD(P->d[1] + o),
                   dz = PK_LOAD(P->d[2] + o);
        const pk_v pad = PK_LOAD(P->pad + o);
        const pk_v T = PK_MUL(PK_ADD(PK_LOAD(P->tcf + o), pad), grow);
        const pk_v ex = PK_ADD(ox, PK_MUL(T, dx)), ey = PK_ADD(oy, PK_MUL(T, dy)),
                   ez = PK_ADD(oz, PK_MUL(T, dz));
        /* NaN-free: finite origins, T possibly +inf (then mc is inf) */
        mc = PK_MAX(PK_MAX(PK_MAX(PK_ABS(ox), PK_ABS(oy)), PK_ABS(oz)), mc);
        mc = PK_MAX(PK_MAX(PK_MAX(PK_ABS(ex), PK_ABS(ey)), PK_ABS(ez)), mc);
        pdm = PK_MAX(PK_MUL(pad, PK_MAX(PK_MAX(PK_ABS(dx), PK_ABS(dy)), PK_ABS(dz))), pdm);
#define PK_CONE_DOT(a, b, c, x, y, z) PK_ADD(PK_ADD(PK_MUL(a, x), PK_MUL(b, y)), PK_MUL(c, z))
        h0 = PK_MAX(PK_MAX(PK_CONE_DOT(n0x, n0y, n0z, ox, oy, oz),
                           PK_CONE_DOT(n0x, n0y, n0z, ex, ey, ez)), h0);
        h1 = PK_MAX(PK_MAX(PK_CONE_DOT(n1x, n1y, n1z, ox, oy, oz),
                           PK_CONE_DOT(n1x, n1y, n1z, ex, ey, ez)), h1);
        const pk_v w0 = PK_CONE_DOT(vx, vy, vz, ox, oy, oz), w1 = PK_CONE_DOT(vx, vy, vz, ex, ey, ez);
#undef PK_CONE_DOT
        vmax = PK_MAX(PK_MAX(w0, w1), vmax);
        vmin = PK_MIN(PK_MIN(w0, w1), vmin);
    }
    /* the root's boxes bound every box below them */
    {
        const float *rec = tt_rtc_node(t, 0);
        const uint32_t used = tt_rtc_used(t, rec);
        for (uint32_t i = 0; i < t->S; i += PK_L) {
            const pk_m um = PK_MASK(used >> i & PK_LANES);
            for (int k = 0; k < 6; k++)
                mc = PK_MAX(PK_BLEND(um, zero, PK_ABS(PK_LOADU(tt_rtc_boxes(rec) + k * t->S + i))),
                            mc);
        }
    }
    const float Mc = PK_HMAX(mc), pd = PK_HMAX(pdm);
    if (!(Mc < 0x1p100f && pd < 0x1p100f)) return;
    const float hp[4] = {PK_HMAX(h0), PK_HMAX(h1), PK_HMAX(vmax), -PK_HMIN(vmin)};
    /* the margin: the boxes grown by E, the roundings of n x (at most a
     * few ulps of |n|_1 Mc each side) */
    const float E = Mc * 0x1p-17f + pd * 1.01f;
    for (int p = 0; p < 4; p++) {
        const float n1 = fabsf(P->cn[p][0]) + fabsf(P->cn[p][1]) + fabsf(P->cn[p][2]);
        /* no n x of a box or end can overflow */
        if (!(n1 * Mc < 0x1p100f)) return;
        const float H = hp[p] + n1 * (E + Mc * 0x1p-17f);
        P->ch[p] = H + fabsf(H) * 0x1p-20f;
        if (!(fabsf(P->ch[p]) < 0x1p120f)) return;
    }
    P->cone = 1;
}

#endif
