/* The PLY header: format, elements and their properties, and which of them
 * carry the geometry (vertex x, y, z and the face's vertex index list). */
#ifndef TT_IO_PLY_HEADER_H
#define TT_IO_PLY_HEADER_H

#include <stddef.h>
#include <stdint.h>

#include "core/context.h"

typedef enum ply_format { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE } ply_format;

typedef enum ply_type {
    PLY_INT8, PLY_UINT8, PLY_INT16, PLY_UINT16, PLY_INT32, PLY_UINT32, PLY_FLOAT32, PLY_FLOAT64
} ply_type;

/* What a property means to us; everything else is skipped. */
typedef enum ply_role { ROLE_NONE, ROLE_X, ROLE_Y, ROLE_Z, ROLE_INDICES } ply_role;

typedef struct ply_property {
    const char *name; /* points into the file, not NUL-terminated           */
    size_t name_len;
    int is_list;
    ply_type type;       /* of the value, or of the list's items            */
    ply_type count_type; /* lists only                                      */
    ply_role role;
    size_t element;      /* index of the element it belongs to             */
} ply_property;

typedef struct ply_element {
    const char *name;
    size_t name_len;
    uint64_t count;
    size_t first_property, property_count; /* into ply_header.properties   */
    size_t line;                           /* of its "element" line        */
} ply_element;

typedef struct ply_header {
    ply_format format;
    ply_element *elements;
    size_t element_count, element_cap;
    ply_property *properties;
    size_t property_count, property_cap;
    /* An open-addressing hash set of the element names and, per element,
     * its property names, for the duplicate checks (ply_header.c). */
    size_t *names;
    size_t name_cap, name_count;
    size_t vertex_element, face_element; /* indices into elements           */
    size_t body_offset;                  /* first byte after end_header    */
    size_t body_line;                    /* line number of that byte       */
} ply_header;

/* Parses and validates the header of data[0, size): known format and types,
 * x/y/z and a face index list present, element counts that the rest of the
 * file could hold (so later allocations are bounded by the file size). */
tt_status tt_ply_header_parse(tt_context *ctx, const char *name, const char *data, size_t size,
                              ply_header *h);
void tt_ply_header_free(tt_context *ctx, ply_header *h);

/* printf arguments for "%.*s" with a name from the file, capped so that a
 * giant token cannot flood a message. */
#define NAME_ARG(s, len) (int)((len) > 64 ? 64 : (len)), (s)

/* Bytes of one binary value. */
size_t tt_ply_type_size(ply_type t);
const char *tt_ply_type_name(ply_type t);
int tt_ply_type_is_float(ply_type t);

#endif
