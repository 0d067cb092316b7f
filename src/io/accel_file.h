/* The container of a saved structure (docs/accel-file.md): a fixed header,
 * a table of typed sections, and the sections themselves, each 64-byte
 * aligned so that a structure's arrays can be used in place from a
 * read-only mapping of the file (processes mapping one file share its
 * pages). The container knows nothing of any structure: a structure's
 * save/load entries (accel.h) hand it sections and read them back; what it
 * checks is everything a structure cannot: magic, byte order, version,
 * sizes, both checksums (xxHash XXH3-64), the scene's content hash and the
 * section table's bounds. */
#ifndef TT_IO_ACCEL_FILE_H
#define TT_IO_ACCEL_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "core/context.h"
#include "io/scene.h"

#define TT_AF_MAGIC "TTACCEL\n"
#define TT_AF_ENDIAN 0x01020304u
/* The container's version; a structure's own record format has its own
 * (layout_version), so either can change alone. */
#define TT_AF_VERSION 2u /* 2: the options gained split_budget */
#define TT_AF_HEADER_BYTES 256u
#define TT_AF_ALIGN 64u
#define TT_AF_MAX_SECTIONS 64u

/* The header as stored: host byte order, which `endian` lets a reader
 * check. Every field is fixed-width and the struct has no padding. */
typedef struct tt_af_header {
    char magic[8];
    uint32_t endian;         /* TT_AF_ENDIAN as written                       */
    uint32_t version;        /* TT_AF_VERSION                                 */
    uint32_t header_bytes;   /* TT_AF_HEADER_BYTES                            */
    uint32_t section_count;  /* entries of the table after the header         */
    char structure[16];      /* the vtable's name, NUL-padded                 */
    uint32_t layout;         /* the structure's layout id                     */
    uint32_t layout_version; /* the version of that layout's records          */
    uint32_t isa;            /* tt_isa the saving process traced with (info)  */
    uint32_t block_width;    /* triangle lanes a SIMD block (TT_TRI_BLOCK_W)  */
    uint32_t align;          /* TT_AF_ALIGN                                   */
    uint32_t reserved;
    uint64_t triangles;      /* the scene's triangle count                    */
    uint64_t scene_hash;     /* tt_af_scene_hash of the scene                 */
    uint64_t file_bytes;     /* the whole file                                */
    uint64_t payload_checksum; /* XXH3-64 of bytes [header_bytes, file_bytes) */
    double build_s;          /* the build's time when saved (info)            */
    char scene_name[64];     /* the scene's name as the saver gave it (info)  */
    char library[16];        /* tt_version() of the saver (info)              */
    uint8_t unused[64];      /* zero                                          */
    uint64_t header_checksum; /* XXH3-64 of the 248 bytes before it           */
} tt_af_header;

_Static_assert(sizeof(tt_af_header) == TT_AF_HEADER_BYTES, "the header is 256 bytes");

/* One entry of the section table (24 bytes). */
typedef struct tt_af_entry {
    uint32_t id;        /* the structure's section id                        */
    uint32_t elem;      /* bytes an element                                  */
    uint64_t count;     /* elements                                          */
    uint64_t offset;    /* from the file's start, a multiple of TT_AF_ALIGN  */
} tt_af_entry;

/* A section to write. */
typedef struct tt_af_section {
    uint32_t id, elem;
    uint64_t count;
    const void *data;
} tt_af_section;

/* What a structure's save entry fills in. */
typedef struct tt_af_writer {
    uint32_t layout, layout_version;
    uint32_t count;
    tt_af_section section[TT_AF_MAX_SECTIONS];
    uint64_t small[512]; /* copies of small sections (tt_af_add_copy)     */
    size_t small_used;   /* in uint64_t units                            */
} tt_af_writer;

/* Adds a section (the data must live until tt_af_write returns). */
tt_status tt_af_add(tt_context *ctx, tt_af_writer *w, uint32_t id, uint32_t elem, uint64_t count,
                    const void *data);

/* Adds a copy of a small section (scalars built on the stack). */
tt_status tt_af_add_copy(tt_context *ctx, tt_af_writer *w, uint32_t id, uint32_t elem,
                         uint64_t count, const void *data);

/* The content hash a file is tied to: XXH3-64 of the scene's flat
 * triangle array (9 floats a triangle, load order), seeded with the count. */
uint64_t tt_af_scene_hash(const tt_scene *scene);

/* Writes the file (to PATH.tmp, then renamed over PATH, so a reader never
 * sees half a file). structure: the vtable name; scene_name may be NULL. */
tt_status tt_af_write(tt_context *ctx, const char *path, const char *structure, tt_isa isa,
                      double build_s, const tt_scene *scene, const char *scene_name,
                      const tt_af_writer *w);

/* An opened, verified file. */
typedef struct tt_af_file {
    const uint8_t *data;
    size_t size;
    int mapped;          /* data is an mmap of the file (munmap on close)    */
    const tt_af_header *h;
    const tt_af_entry *table;
    char name[256];      /* the path, for messages                          */
} tt_af_file;

/* Maps the file read-only and verifies the container (magic, byte order,
 * versions, sizes, checksums, table bounds). Errors name the file and what
 * is wrong. */
tt_status tt_af_open(tt_context *ctx, const char *path, tt_af_file *out);
/* The same over bytes in memory (not copied; they must stay alive and be
 * 64-byte aligned for the structures to use them in place; else refused).
 * verify_checksums = 0 is for the fuzzer only (to reach the structures'
 * validation past the checksums). */
tt_status tt_af_open_memory(tt_context *ctx, const char *name, const void *data, size_t size,
                            int verify_checksums, tt_af_file *out);
void tt_af_close(tt_af_file *f);

/* Checks that the file was made for this scene (hash and triangle count);
 * the error names the file and the scene it was saved for. */
tt_status tt_af_check_scene(tt_context *ctx, const tt_af_file *f, const tt_scene *scene);

/* Section `id`: its data and element count, checked to have `elem` bytes an
 * element; a missing or mistyped section is an error naming the file. */
tt_status tt_af_get(tt_context *ctx, const tt_af_file *f, uint32_t id, uint32_t elem,
                    const void **data, uint64_t *count);
/* The same, also requiring exactly `count` elements. */
tt_status tt_af_get_n(tt_context *ctx, const tt_af_file *f, uint32_t id, uint32_t elem,
                      uint64_t count, const void **data);

/* A structure's error about the file's content: "FILE: rtree: <what>". */
tt_status tt_af_bad(tt_context *ctx, const tt_af_file *f, const char *fmt, ...)
    TT_PRINTF(3, 4);

/* The build options as a section of 32-bit words (fixed order; docs). */
#define TT_AF_OPTION_WORDS 21u
void tt_af_options_pack(const tt_build_options *o, uint32_t out[TT_AF_OPTION_WORDS]);
/* Unpacks into *o (accel left as is) and checks every enum's range. */
tt_status tt_af_options_unpack(tt_context *ctx, const tt_af_file *f,
                               const uint32_t in[TT_AF_OPTION_WORDS], tt_build_options *o);

#endif
