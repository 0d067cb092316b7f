/* Per-tile trace loops, a template compiled twice like the traversals (see
 * accel/stats_variant.h): with TT_STATS 0 the fast variant, calling the
 * structure's fast entry points; with TT_STATS 1 the counting variant. The
 * two must trace exactly the same rays, so they share this one text.
 * Included only by trace_pass.c, which defines tile_bounds (tt_ray_stats_add is accel/accel.h's). */

/* Primary rays of one tile as one packet (a camera tile is coherent: auto
 * and on alike). The packet has no end hints: the shadow rays start at the
 * root. The counting variant adds the rays' counts to *sum and the packet
 * counts to the frame's. */
static void TT_VARIANT(primary_packet)(tt_frame *f, uint32_t x0, uint32_t y0, uint32_t x1,
                                       uint32_t y1, tt_ray_stats *sum)
{
    const tt_accel *accel = f->accel;
    tt_packet_rays w;
    tt_hit h[TT_TILE * TT_TILE];
    uint32_t n = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++) {
            tt_ray r;
            tt_camera_basis_ray(&f->basis, x, y, &r);
            tt_packet_ray_set(&w, n++, r.org, r.dir, r.tmin, r.tmax);
        }
    if (n == 0) return; /* (a tile is never empty; this tells the compiler) */
    w.n = n;
#if TT_STATS
    tt_packet_stats ps;
    memset(&ps, 0, sizeof ps);
    accel->vt->intersect_packet_stats(accel, &w, h, &ps);
    tt_ray_stats_add(sum, &ps.rays);
    packet_stats_add(&f->packet_primary, &ps);
#else
    (void)sum;
    accel->vt->intersect_packet(accel, &w, h);
#endif
    n = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++, n++) {
            const size_t i = (size_t)y * f->width + x;
            f->prim[i] = h[n].prim;
            f->t[i] = h[n].prim == TT_INVALID_ID ? TT_INF : h[n].t;
            f->end_hint[i] = TT_INVALID_ID;
        }
}

/* Primary rays of one tile, all started from the eye's hint. */
static void TT_VARIANT(primary_tile)(tt_frame *f, uint32_t tile, tt_ray_stats *sum)
{
    const tt_accel *accel = f->accel;
    const tt_accel_vtable *vt = accel->vt;
    uint32_t x0, y0, x1, y1;
    tile_bounds(f, tile, &x0, &y0, &x1, &y1);
    (void)sum;
    /* per-pixel counts need each ray's own walk */
    if (f->packets != TT_PACKETS_OFF && !(TT_STATS && f->pixel_stats[TT_HEAT_NODES])) {
        TT_VARIANT(primary_packet)(f, x0, y0, x1, y1, sum);
        return;
    }
    for (uint32_t y = y0; y < y1; y++) {
        for (uint32_t x = x0; x < x1; x++) {
            size_t i = (size_t)y * f->width + x;
            tt_ray r;
            tt_wray w;
            tt_hit h;
            tt_trace_args args = {f->eye_hint, TT_INVALID_ID, NULL};
            tt_camera_basis_ray(&f->basis, x, y, &r);
            tt_wray_init(&w, r.org, r.dir, r.tmin, r.tmax);
#if TT_STATS
            tt_ray_stats one;
            memset(&one, 0, sizeof one);
            args.stats = &one;
            vt->intersect_stats(accel, &w, &h, &args, &one);
            tt_ray_stats_add(sum, &one);
            if (f->pixel_stats[TT_HEAT_NODES]) store_pixel_stats(f, i, &one);
#else
            vt->intersect(accel, &w, &h, &args);
#endif
            f->prim[i] = h.prim;
            f->t[i] = h.prim == TT_INVALID_ID ? TT_INF : h.t;
            f->end_hint[i] = args.end_hint;
        }
    }
}

/* Shadow rays of one tile's primary hits, each started from the node its
 * primary ray ended in. With the kd-tree's caster option, the node where
 * the tile's last occluded shadow ray ended also goes in: the kd-tree takes
 * it in args.end_hint on input (start_hint stays the ray's own start) and
 * searches that caster's box first. The caster is forgotten at every tile
 * so that the result does not depend on which thread traced which tile
 * before. */
static void TT_VARIANT(shadow_tile)(tt_frame *f, uint32_t tile, tt_ray_stats *sum)
{
    const tt_accel *accel = f->accel;
    const tt_accel_vtable *vt = accel->vt;
    uint32_t x0, y0, x1, y1;
    uint32_t caster = TT_INVALID_ID;
    tile_bounds(f, tile, &x0, &y0, &x1, &y1);
    (void)sum;
    if (f->packets != TT_PACKETS_OFF && !f->caster_hint) {
        /* the tile's shadow rays towards the light: one packet when
         * coherent (or always with TT_PACKETS_ON), else ray by ray */
        tt_packet_rays w;
        uint8_t occ[TT_TILE * TT_TILE];
        uint32_t idx[TT_TILE * TT_TILE], hint[TT_TILE * TT_TILE];
        uint32_t n = 0;
        for (uint32_t y = y0; y < y1; y++)
            for (uint32_t x = x0; x < x1; x++) {
                const size_t i = (size_t)y * f->width + x;
                f->shadow[i] = 0;
                if (f->prim[i] == TT_INVALID_ID) continue;
                tt_ray r, s;
                tt_hit h = {f->t[i], 0.0f, 0.0f, f->prim[i]};
                tt_camera_basis_ray(&f->basis, x, y, &r);
                if (!tt_shadow_ray_eps(f->scene, f->camera, f->eps, &r, &h, &s)) continue;
                tt_packet_ray_set(&w, n, s.org, s.dir, s.tmin, s.tmax);
                hint[n] = f->end_hint[i];
                idx[n++] = (uint32_t)i;
            }
        w.n = n;
        if (f->packets == TT_PACKETS_ON || tt_packet_coherent(&w)) {
#if TT_STATS
            tt_packet_stats ps;
            memset(&ps, 0, sizeof ps);
            vt->occluded_packet_stats(accel, &w, occ, &ps);
            tt_ray_stats_add(sum, &ps.rays);
            packet_stats_add(&f->packet_shadow, &ps);
#else
            vt->occluded_packet(accel, &w, occ);
#endif
        } else {
            for (uint32_t j = 0; j < n; j++) {
                tt_trace_args args = {hint[j], TT_INVALID_ID, NULL};
                tt_wray wj;
                tt_packet_ray_wray(&w, j, &wj);
#if TT_STATS
                args.stats = sum;
                occ[j] = (uint8_t)(vt->occluded_stats(accel, &wj, &args, sum) != 0);
#else
                occ[j] = (uint8_t)(vt->occluded(accel, &wj, &args) != 0);
#endif
            }
        }
        for (uint32_t j = 0; j < n; j++) f->shadow[idx[j]] = occ[j];
        return;
    }
    for (uint32_t y = y0; y < y1; y++) {
        for (uint32_t x = x0; x < x1; x++) {
            size_t i = (size_t)y * f->width + x;
            int occluded = 0;
            if (f->prim[i] != TT_INVALID_ID) {
                tt_ray r, s;
                tt_hit h = {f->t[i], 0.0f, 0.0f, f->prim[i]};
                tt_camera_basis_ray(&f->basis, x, y, &r);
                if (tt_shadow_ray_eps(f->scene, f->camera, f->eps, &r, &h, &s)) {
                    tt_wray w;
                    tt_trace_args args = {f->end_hint[i], f->caster_hint ? caster : TT_INVALID_ID,
                                          NULL};
                    tt_wray_init(&w, s.org, s.dir, s.tmin, s.tmax);
#if TT_STATS
                    args.stats = sum;
                    occluded = vt->occluded_stats(accel, &w, &args, sum);
#else
                    occluded = vt->occluded(accel, &w, &args);
#endif
                    if (occluded && f->caster_hint) caster = args.end_hint;
                }
            }
            f->shadow[i] = (uint8_t)(occluded != 0);
        }
    }
}
