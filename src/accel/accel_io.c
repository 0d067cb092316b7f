/* Saving and loading built structures (the public tt_accel_save /
 * tt_accel_load): the container (io/accel_file.c) checks the file, the
 * structure's save/load vtable entries (e.g. rtree/rtree_io.c,
 * kdtree/kd_io.c) write and read their own sections. What every structure
 * shares is stored here: the build options (section TT_AF_SEC_OPTIONS). */
#include <string.h>

#include "accel/accel.h"
#include "accel/accel_io.h"
#include "core/isa.h"
#include "io/accel_file.h"

tt_status tt_accel_save(const tt_accel *a, const char *path, const char *scene_name)
{
    if (!a || !path) return TT_ERR_INVALID_ARGUMENT;
    if (!a->vt->save)
        return tt_error(a->ctx, TT_ERR_UNSUPPORTED, "%s: structure '%s' cannot be saved: %s", path,
                        a->vt->name, a->vt->no_save ? a->vt->no_save : "no save entry");
    tt_af_writer w;
    memset(&w, 0, sizeof w);
    uint32_t opt[TT_AF_OPTION_WORDS];
    tt_af_options_pack(&a->options, opt);
    tt_status st = tt_af_add_copy(a->ctx, &w, TT_AF_SEC_OPTIONS, 4, TT_AF_OPTION_WORDS, opt);
    if (st == TT_OK) st = a->vt->save(a, &w);
    if (st == TT_OK)
        st = tt_af_write(a->ctx, path, a->vt->name, a->isa, a->build_s, a->scene, scene_name, &w);
    return st;
}

void tt_accel_unload(tt_accel *a)
{
    if (a->impl && a->vt->unload) a->vt->unload(a);
    if (a->file) {
        tt_af_close(a->file);
        tt_free(a->ctx, a->file);
    }
    tt_free(a->ctx, a);
}

tt_status tt_accel_load_opened(tt_context *ctx, const tt_scene *scene, tt_af_file *file, tt_isa isa,
                               tt_accel **out)
{
    double t0 = tt_now();
    *out = NULL;
    tt_status st = tt_af_check_scene(ctx, file, scene);
    const tt_accel_vtable *vt = NULL;
    if (st == TT_OK) {
        vt = tt_accel_find(file->h->structure);
        if (!vt)
            st = tt_error(ctx, TT_ERR_UNSUPPORTED,
                          "%s: holds structure '%s', which this build does not have", file->name,
                          file->h->structure);
        else if (!vt->load || !vt->unload)
            st = tt_error(ctx, TT_ERR_UNSUPPORTED, "%s: structure '%s' cannot be loaded: %s",
                          file->name, vt->name, vt->no_save ? vt->no_save : "no load entry");
    }
    tt_isa resolved = TT_ISA_SCALAR;
    if (st == TT_OK) st = tt_isa_resolve(ctx, isa, &resolved);
    tt_accel *a = NULL;
    if (st == TT_OK) {
        a = tt_calloc(ctx, 1, sizeof *a);
        if (!a) st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", file->name);
    }
    if (st != TT_OK) {
        tt_af_close(file);
        tt_free(ctx, file);
        return st;
    }
    a->vt = vt;
    a->ctx = ctx;
    a->scene = scene;
    a->version = scene->version; /* its content hash matched this scene as it is now */
    a->file = file;
    a->isa = resolved;
    tt_build_options_default(&a->options);
    const void *opt;
    st = tt_af_get_n(ctx, file, TT_AF_SEC_OPTIONS, 4, TT_AF_OPTION_WORDS, &opt);
    if (st == TT_OK) st = tt_af_options_unpack(ctx, file, opt, &a->options);
    a->options.accel = vt->name;
    a->options.isa = isa;
    if (st == TT_OK) st = vt->load(a, file);
    a->build_s = tt_now() - t0;
    if (st != TT_OK) {
        tt_accel_unload(a);
        return st;
    }
    *out = a;
    return TT_OK;
}

tt_status tt_accel_load(tt_context *ctx, const tt_scene *scene, const char *path, tt_isa isa,
                        tt_accel **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!scene || !path)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_accel_load: no scene or no path");
    const double t0 = tt_now(); /* the whole load: map, checksums, validation */
    tt_af_file *f = tt_calloc(ctx, 1, sizeof *f);
    if (!f) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    tt_status st = tt_af_open(ctx, path, f);
    if (st != TT_OK) {
        tt_free(ctx, f);
        return st;
    }
    st = tt_accel_load_opened(ctx, scene, f, isa, out);
    if (st == TT_OK) (*out)->build_s = tt_now() - t0;
    return st;
}

int tt_accel_loaded(const tt_accel *a) { return a && a->file != NULL; }

tt_status tt_accel_options(const tt_accel *a, tt_build_options *out)
{
    if (!a || !out) return TT_ERR_INVALID_ARGUMENT;
    *out = a->options;
    return TT_OK;
}
