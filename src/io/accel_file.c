/* The saved-structure container (accel_file.h; the format is
 * docs/accel-file.md). Reading maps the file and checks, in this order,
 * what a hostile or damaged file could get wrong: its size against the
 * header, magic, byte order, version, the header's checksum, the payload's
 * checksum, then the section table (bounds, alignment, overflow), so that a
 * structure's loader only ever sees sections lying wholly inside the file. */
#include "io/accel_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
/* the implementation inlined here (xxhash.h, XXH_INLINE_ALL): no library to link */
#define XXH_INLINE_ALL
#include <xxhash.h>

#include "geometry/tri_block.h"

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

uint64_t tt_af_scene_hash(const tt_scene *scene)
{
    return XXH3_64bits_withSeed(scene->tri, scene->triangle_count * 9 * sizeof(float),
                                (XXH64_hash_t)scene->triangle_count);
}

tt_status tt_af_add(tt_context *ctx, tt_af_writer *w, uint32_t id, uint32_t elem, uint64_t count,
                    const void *data)
{
    if (w->count >= TT_AF_MAX_SECTIONS)
        return tt_error(ctx, TT_ERR_INTERNAL, "accel file: more than %u sections",
                        TT_AF_MAX_SECTIONS);
    w->section[w->count++] = (tt_af_section){id, elem, count, data};
    return TT_OK;
}

tt_status tt_af_add_copy(tt_context *ctx, tt_af_writer *w, uint32_t id, uint32_t elem,
                         uint64_t count, const void *data)
{
    const size_t bytes = (size_t)(count * elem), words = (bytes + 7) / 8;
    const size_t room = sizeof w->small / sizeof w->small[0] - w->small_used;
    if (count > 4096 || words > room)
        return tt_error(ctx, TT_ERR_INTERNAL, "accel file: small section %u too large", id);
    uint64_t *dst = w->small + w->small_used;
    memcpy(dst, data, bytes);
    w->small_used += words;
    return tt_af_add(ctx, w, id, elem, count, dst);
}

static uint64_t align_up(uint64_t x) { return (x + TT_AF_ALIGN - 1) & ~(uint64_t)(TT_AF_ALIGN - 1); }

/* ------------------------------------------------------------------ write */

static int write_all(FILE *fp, const void *p, size_t n, XXH3_state_t *st)
{
    if (st) XXH3_64bits_update(st, p, n);
    return n == 0 || fwrite(p, 1, n, fp) == n;
}

static int write_pad(FILE *fp, uint64_t at, XXH3_state_t *st)
{
    static const uint8_t zero[TT_AF_ALIGN];
    return write_all(fp, zero, (size_t)(align_up(at) - at), st);
}

/* The table and sections (the payload) in file order. */
static int write_payload(FILE *fp, const tt_af_entry *table, const tt_af_writer *w,
                         XXH3_state_t *st)
{
    uint64_t at = TT_AF_HEADER_BYTES;
    if (!write_all(fp, table, w->count * sizeof *table, st)) return 0;
    at += w->count * sizeof *table;
    for (uint32_t i = 0; i < w->count; i++) {
        if (!write_pad(fp, at, st)) return 0;
        at = table[i].offset;
        const size_t n = (size_t)(table[i].count * table[i].elem);
        if (!write_all(fp, w->section[i].data, n, st)) return 0;
        at += n;
    }
    return 1;
}

tt_status tt_af_write(tt_context *ctx, const char *path, const char *structure, tt_isa isa,
                      double build_s, const tt_scene *scene, const char *scene_name,
                      const tt_af_writer *w)
{
    tt_af_entry table[TT_AF_MAX_SECTIONS];
    uint64_t at = TT_AF_HEADER_BYTES + (uint64_t)w->count * sizeof(tt_af_entry);
    for (uint32_t i = 0; i < w->count; i++) {
        const tt_af_section *s = &w->section[i];
        at = align_up(at);
        table[i] = (tt_af_entry){s->id, s->elem, s->count, at};
        at += s->count * s->elem;
    }
    tt_af_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, TT_AF_MAGIC, 8);
    h.endian = TT_AF_ENDIAN;
    h.version = TT_AF_VERSION;
    h.header_bytes = TT_AF_HEADER_BYTES;
    h.section_count = w->count;
    snprintf(h.structure, sizeof h.structure, "%s", structure);
    h.layout = w->layout;
    h.layout_version = w->layout_version;
    h.isa = (uint32_t)isa;
    h.block_width = TT_TRI_BLOCK_W;
    h.align = TT_AF_ALIGN;
    h.triangles = scene->triangle_count;
    h.scene_hash = tt_af_scene_hash(scene);
    h.file_bytes = at;
    h.build_s = build_s;
    if (scene_name) snprintf(h.scene_name, sizeof h.scene_name, "%s", base_name(scene_name));
    snprintf(h.library, sizeof h.library, "%s", tt_version());

    XXH3_state_t *st = XXH3_createState();
    if (!st) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    XXH3_64bits_reset(st);
    /* the checksum first (the payload is in memory): one pass to compute,
     * one to write, so the header goes out complete */
    {
        uint64_t pos = TT_AF_HEADER_BYTES;
        XXH3_64bits_update(st, table, w->count * sizeof *table);
        pos += w->count * sizeof *table;
        static const uint8_t zero[TT_AF_ALIGN];
        for (uint32_t i = 0; i < w->count; i++) {
            XXH3_64bits_update(st, zero, (size_t)(table[i].offset - pos));
            const size_t n = (size_t)(table[i].count * table[i].elem);
            if (n) XXH3_64bits_update(st, w->section[i].data, n);
            pos = table[i].offset + n;
        }
    }
    h.payload_checksum = XXH3_64bits_digest(st);
    XXH3_freeState(st);
    h.header_checksum = XXH3_64bits(&h, offsetof(tt_af_header, header_checksum));

    char tmp[4096];
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: path too long", path);
    FILE *fp = fopen(tmp, "wb");
    if (!fp) return tt_error(ctx, TT_ERR_IO, "%s: cannot create: %s", tmp, strerror(errno));
    int ok = write_all(fp, &h, sizeof h, NULL) && write_payload(fp, table, w, NULL);
    ok = (fclose(fp) == 0) && ok;
    if (!ok) {
        remove(tmp);
        return tt_error(ctx, TT_ERR_IO, "%s: write failed: %s", path, strerror(errno));
    }
    if (rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        return tt_error(ctx, TT_ERR_IO, "%s: cannot rename %s over it: %s", path, tmp, strerror(e));
    }
    return TT_OK;
}

/* ------------------------------------------------------------------- read */

static tt_status bad(tt_context *ctx, const char *name, tt_status st, const char *fmt, ...)
    TT_PRINTF(4, 5);
static tt_status bad(tt_context *ctx, const char *name, tt_status st, const char *fmt, ...)
{
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return tt_error(ctx, st, "%s: %s", name, what);
}

tt_status tt_af_bad(tt_context *ctx, const tt_af_file *f, const char *fmt, ...)
{
    char what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return tt_error(ctx, TT_ERR_PARSE, "%s: %.16s: %s", f->name, f->h->structure, what);
}

static uint32_t swap32(uint32_t v)
{
    return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

static tt_status verify(tt_context *ctx, tt_af_file *f, int verify_checksums)
{
    const char *name = f->name;
    if (f->size < TT_AF_HEADER_BYTES)
        return bad(ctx, name, TT_ERR_PARSE,
                   "truncated: %zu bytes, shorter than the %u-byte header of a treetrace "
                   "structure file", f->size, TT_AF_HEADER_BYTES);
    const tt_af_header *h = (const tt_af_header *)f->data;
    f->h = h;
    if (memcmp(h->magic, TT_AF_MAGIC, 8) != 0)
        return bad(ctx, name, TT_ERR_PARSE,
                   "not a treetrace structure file (no \"TTACCEL\" magic at byte 0)");
    if (h->endian == swap32(TT_AF_ENDIAN))
        return bad(ctx, name, TT_ERR_UNSUPPORTED,
                   "written on a machine of the other byte order; this machine cannot use its "
                   "arrays in place: rebuild the structure here");
    if (h->endian != TT_AF_ENDIAN)
        return bad(ctx, name, TT_ERR_PARSE, "byte-order mark 0x%08x at byte 8 is damaged",
                   h->endian);
    if (h->version != TT_AF_VERSION)
        return bad(ctx, name, TT_ERR_UNSUPPORTED,
                   "container version %u; this library (%s) reads version %u: rebuild the "
                   "structure with this library", h->version, tt_version(), TT_AF_VERSION);
    if (verify_checksums &&
        XXH3_64bits(h, offsetof(tt_af_header, header_checksum)) != h->header_checksum)
        return bad(ctx, name, TT_ERR_PARSE, "header checksum mismatch (bytes 0-247 damaged)");
    if (h->header_bytes != TT_AF_HEADER_BYTES || h->align != TT_AF_ALIGN)
        return bad(ctx, name, TT_ERR_PARSE, "header size %u / alignment %u, expected %u / %u",
                   h->header_bytes, h->align, TT_AF_HEADER_BYTES, TT_AF_ALIGN);
    if (h->file_bytes != f->size)
        return bad(ctx, name, TT_ERR_PARSE,
                   "%s: the header says %llu bytes, the file has %zu",
                   h->file_bytes > f->size ? "truncated" : "trailing bytes",
                   (unsigned long long)h->file_bytes, f->size);
    if (h->block_width != TT_TRI_BLOCK_W)
        return bad(ctx, name, TT_ERR_UNSUPPORTED,
                   "written with %u-lane triangle blocks; this library's SIMD layout has %d "
                   "lanes: rebuild the structure here", h->block_width, TT_TRI_BLOCK_W);
    if (h->structure[sizeof h->structure - 1] != '\0' || h->scene_name[sizeof h->scene_name - 1] ||
        h->library[sizeof h->library - 1])
        return bad(ctx, name, TT_ERR_PARSE, "unterminated name in the header");
    if (h->section_count > TT_AF_MAX_SECTIONS)
        return bad(ctx, name, TT_ERR_PARSE, "%u sections, at most %u", h->section_count,
                   TT_AF_MAX_SECTIONS);
    const uint64_t table_end =
        TT_AF_HEADER_BYTES + (uint64_t)h->section_count * sizeof(tt_af_entry);
    if (table_end > f->size)
        return bad(ctx, name, TT_ERR_PARSE, "truncated inside the section table (%u entries)",
                   h->section_count);
    if (verify_checksums) {
        uint64_t sum = XXH3_64bits(f->data + TT_AF_HEADER_BYTES, f->size - TT_AF_HEADER_BYTES);
        if (sum != h->payload_checksum)
            return bad(ctx, name, TT_ERR_PARSE,
                       "payload checksum mismatch (XXH3 0x%016llx, header says 0x%016llx): "
                       "the file is damaged", (unsigned long long)sum,
                       (unsigned long long)h->payload_checksum);
    }
    f->table = (const tt_af_entry *)(f->data + TT_AF_HEADER_BYTES);
    uint64_t prev_end = table_end;
    for (uint32_t i = 0; i < h->section_count; i++) {
        const tt_af_entry *e = &f->table[i];
        if (e->elem == 0 || e->elem > 4096)
            return bad(ctx, name, TT_ERR_PARSE, "section %u: element size %u", i, e->elem);
        if (e->offset % TT_AF_ALIGN || e->offset < prev_end || e->offset > f->size)
            return bad(ctx, name, TT_ERR_PARSE,
                       "section %u: offset %llu is misaligned, overlapping or past the end", i,
                       (unsigned long long)e->offset);
        if (e->count > (f->size - e->offset) / e->elem)
            return bad(ctx, name, TT_ERR_PARSE,
                       "section %u: %llu elements of %u bytes run past the end of the file "
                       "(%zu bytes)", i, (unsigned long long)e->count, e->elem, f->size);
        prev_end = e->offset + e->count * e->elem;
    }
    return TT_OK;
}

tt_status tt_af_open_memory(tt_context *ctx, const char *name, const void *data, size_t size,
                            int verify_checksums, tt_af_file *out)
{
    memset(out, 0, sizeof *out);
    snprintf(out->name, sizeof out->name, "%s", name ? name : "(memory)");
    if (!data && size) return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: no data", out->name);
    if ((uintptr_t)data % TT_AF_ALIGN)
        return bad(ctx, out->name, TT_ERR_INVALID_ARGUMENT,
                   "the bytes in memory are not %u-byte aligned", TT_AF_ALIGN);
    out->data = data;
    out->size = size;
    return verify(ctx, out, verify_checksums);
}

tt_status tt_af_open(tt_context *ctx, const char *path, tt_af_file *out)
{
    memset(out, 0, sizeof *out);
    snprintf(out->name, sizeof out->name, "%s", path);
    int fd = open(path, O_RDONLY);
    if (fd < 0) return bad(ctx, path, TT_ERR_IO, "cannot open: %s", strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(fd);
        return bad(ctx, path, TT_ERR_IO, "not a regular file");
    }
    if (sb.st_size == 0) {
        close(fd);
        return bad(ctx, path, TT_ERR_PARSE, "empty file (truncated)");
    }
    /* Read-only and shared: every process mapping the file shares its page
     * cache pages; the structures never write to their arrays. */
    void *map = mmap(NULL, (size_t)sb.st_size, PROT_READ, MAP_SHARED, fd, 0);
    close(fd);
    if (map == MAP_FAILED) return bad(ctx, path, TT_ERR_IO, "cannot map: %s", strerror(errno));
    out->data = map;
    out->size = (size_t)sb.st_size;
    out->mapped = 1;
    tt_status st = verify(ctx, out, 1);
    if (st != TT_OK) tt_af_close(out);
    return st;
}

void tt_af_close(tt_af_file *f)
{
    if (f->mapped && f->data) munmap((void *)f->data, f->size);
    f->data = NULL;
    f->mapped = 0;
}

tt_status tt_af_check_scene(tt_context *ctx, const tt_af_file *f, const tt_scene *scene)
{
    const tt_af_header *h = f->h;
    uint64_t hash = tt_af_scene_hash(scene);
    if (h->triangles != scene->triangle_count || h->scene_hash != hash)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: saved for another scene: '%s' (%llu triangles, content hash "
                        "%016llx), not this one (%zu triangles, hash %016llx)",
                        f->name, h->scene_name[0] ? h->scene_name : "unnamed",
                        (unsigned long long)h->triangles, (unsigned long long)h->scene_hash,
                        scene->triangle_count, (unsigned long long)hash);
    return TT_OK;
}

tt_status tt_af_get(tt_context *ctx, const tt_af_file *f, uint32_t id, uint32_t elem,
                    const void **data, uint64_t *count)
{
    for (uint32_t i = 0; i < f->h->section_count; i++) {
        const tt_af_entry *e = &f->table[i];
        if (e->id != id) continue;
        if (e->elem != elem)
            return tt_af_bad(ctx, f, "section %u has %u-byte elements, expected %u", id, e->elem,
                             elem);
        *data = f->data + e->offset;
        *count = e->count;
        return TT_OK;
    }
    return tt_af_bad(ctx, f, "section %u is missing", id);
}

tt_status tt_af_get_n(tt_context *ctx, const tt_af_file *f, uint32_t id, uint32_t elem,
                      uint64_t count, const void **data)
{
    uint64_t n = 0;
    tt_status st = tt_af_get(ctx, f, id, elem, data, &n);
    if (st == TT_OK && n != count)
        return tt_af_bad(ctx, f, "section %u has %llu elements, expected %llu", id,
                         (unsigned long long)n, (unsigned long long)count);
    return st;
}

/* ---------------------------------------------------------------- options */

static uint32_t fbits(float x)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    return u;
}
static float bitsf(uint32_t u)
{
    float x;
    memcpy(&x, &u, 4);
    return x;
}

void tt_af_options_pack(const tt_build_options *o, uint32_t w[TT_AF_OPTION_WORDS])
{
    const tt_rtree_options *r = &o->rtree;
    const tt_kdtree_options *k = &o->kdtree;
    const uint32_t v[TT_AF_OPTION_WORDS] = {
        (uint32_t)o->isa,         (uint32_t)r->build,        (uint32_t)r->layout,
        (uint32_t)r->strategy,    (uint32_t)r->m,            (uint32_t)r->M,
        (uint32_t)r->reinsert,    fbits(r->reinsert_fraction), (uint32_t)r->reinsert_far,
        (uint32_t)r->split,       (uint32_t)r->traversal,    (uint32_t)k->builder,
        (uint32_t)k->dmin,        fbits(k->cost_traversal),  fbits(k->cost_intersect),
        fbits(k->empty_bonus),    (uint32_t)k->max_depth,    (uint32_t)k->traversal,
        (uint32_t)k->shadow_caster_hint, (uint32_t)o->embree.quality, fbits(r->split_budget)};
    memcpy(w, v, sizeof v);
}

tt_status tt_af_options_unpack(tt_context *ctx, const tt_af_file *f,
                               const uint32_t w[TT_AF_OPTION_WORDS], tt_build_options *o)
{
    tt_rtree_options *r = &o->rtree;
    tt_kdtree_options *k = &o->kdtree;
    if (w[0] > TT_ISA_AVX512 || w[1] > TT_RTREE_BUILD_SAH || w[2] > TT_RTREE_LAYOUT_COMPACT ||
        w[3] > TT_RTREE_RSTAR_SURFACE || w[9] > TT_RTREE_SPLIT_QUADRATIC ||
        w[10] > TT_RTREE_STACK || w[11] > TT_KD_BINNED || w[17] > TT_KD_SEQ || w[19] > TT_EMBREE_LOW ||
        w[4] > 64 || w[5] > 64 || w[6] > 1 || w[8] > 1 || w[18] > 1 ||
        !(bitsf(w[20]) >= 0.0f && bitsf(w[20]) <= 4.0f))
        return tt_af_bad(ctx, f, "the build options section holds an out-of-range value");
    o->isa = (tt_isa)w[0];
    r->build = (tt_rtree_build)w[1];
    r->layout = (tt_rtree_layout)w[2];
    r->strategy = (tt_rtree_strategy)w[3];
    r->m = (int)w[4];
    r->M = (int)w[5];
    r->reinsert = (int)w[6];
    r->reinsert_fraction = bitsf(w[7]);
    r->reinsert_far = (int)w[8];
    r->split = (tt_rtree_split)w[9];
    r->traversal = (tt_rtree_traversal)w[10];
    k->builder = (tt_kd_builder)w[11];
    k->dmin = (int)w[12];
    k->cost_traversal = bitsf(w[13]);
    k->cost_intersect = bitsf(w[14]);
    k->empty_bonus = bitsf(w[15]);
    k->max_depth = (int)w[16];
    k->traversal = (tt_kd_traversal)w[17];
    k->shadow_caster_hint = (int)w[18];
    o->embree.quality = (tt_embree_quality)w[19];
    r->split_budget = bitsf(w[20]);
    return TT_OK;
}
