/* pg_gltf.h - write a glTF 2.0 binary (.glb) through tinygltf, as a C API.
 *
 * The export module describes the file in plain C structs (meshes as float arrays,
 * images as encoded bytes or external URIs, extras as key/value pairs); the C++
 * adapter pg_gltf.cpp builds the tinygltf::Model and lets tinygltf serialise the
 * JSON and the binary chunk. No glTF JSON is written by hand anywhere. */
#ifndef PG_GLTF_H
#define PG_GLTF_H

#include "planetgen/pg_common.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_gltf_image {
    const char *name;
    const char *mime;     /* "image/png" or "image/jpeg" */
    const uint8_t *bytes; /* embedded into the binary chunk when uri is NULL */
    size_t size;
    const char *uri; /* relative file name of an external image, or NULL */
} pg_gltf_image;

/* A key/value pair for an extras object: a number, a string, or an integer. */
typedef struct pg_gltf_extra {
    const char *key;
    const char *string; /* non-NULL: a string value */
    double number;      /* otherwise a number */
    int is_int;         /* number is an integer (written without a fraction) */
} pg_gltf_extra;

#define PG_GLTF_MAX_EXTRAS 8

/* One triangle primitive with its own material. Arrays shared between primitives
 * (same pointer and count) become one shared accessor. */
typedef struct pg_gltf_primitive {
    const char *material_name;
    uint32_t nverts;
    const float *positions; /* nverts x 3 */
    const float *normals;   /* nverts x 3, unit */
    const float *tangents;  /* nverts x 4, unit xyz, w = +-1 */
    const float *texcoords; /* nverts x 2 */
    uint32_t nindices;
    const uint32_t *indices;
    int base_color_image, normal_image; /* image indices, each gets a texture */
    int nextras;                        /* material extras */
    pg_gltf_extra extras[PG_GLTF_MAX_EXTRAS];
} pg_gltf_primitive;

typedef struct pg_gltf_desc {
    const char *generator;
    const char *mesh_name;
    const double *node_rotation; /* quaternion x, y, z, w, or NULL */
    int nprims;
    const pg_gltf_primitive *prims;
    int nimages;
    const pg_gltf_image *images;
    int nscene_extras;
    const pg_gltf_extra *scene_extras;
} pg_gltf_desc;

/* Write the .glb to path (the caller stages and renames it). */
pg_status pg_gltf_write_glb(const char *path, const pg_gltf_desc *d, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
