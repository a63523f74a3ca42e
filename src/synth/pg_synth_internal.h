/* pg_synth_internal.h - shared internals of the synthesis module (not a public API).
 *
 * The preparation pipeline passes a "work" exemplar between its stages: float
 * faces with gutters (channels L, a, b, height*lab_height_scale), then one Gaussian
 * stack level at a time. Tests include this header to recompute appearance vectors
 * from output images with the exemplar's own PCA basis. */
#ifndef PG_SYNTH_INTERNAL_H
#define PG_SYNTH_INTERNAL_H

#include "planetgen/pg_synth.h"

#define PG_SYNTH_NB 25                           /* 5x5 neighbourhood */
#define PG_SYNTH_CH 4                            /* L, a, b, weighted height */
#define PG_SYNTH_RAW (PG_SYNTH_NB * PG_SYNTH_CH) /* 100 raw dims */

/* Float faces with a gutter of width g on every side: nfaces x ext x ext x 4. For a
 * torus, g = 0 and reads wrap; otherwise reads clamp into the extended face. */
typedef struct pg_synth_faces {
    int nfaces, size, gutter, ext;
    bool torus;
    float *px;
} pg_synth_faces;

static inline const float *pg_synth_faces_at(const pg_synth_faces *f, int face, int x, int y) {
    /* x, y are interior coordinates (0..size-1 inside the face proper) */
    if (f->torus) {
        x &= f->size - 1;
        y &= f->size - 1;
    } else {
        x += f->gutter;
        y += f->gutter;
        x = x < 0 ? 0 : (x >= f->ext ? f->ext - 1 : x);
        y = y < 0 ? 0 : (y >= f->ext ? f->ext - 1 : y);
    }
    return f->px +
           (((size_t)face * (size_t)f->ext + (size_t)y) * (size_t)f->ext + (size_t)x) * PG_SYNTH_CH;
}

/* sRGB (0..1, encoded) -> CIE Lab (D65). */
void pg_synth_srgb_to_lab(const float rgb[3], float lab[3]);

/* pg_exemplar_cube.c: reproject an equirect map onto 6 faces with gutter g (plus the
 * finest sRGB8 albedo and height of the face interiors into ex). */
pg_status pg_exemplar_cube_build(const float *albedo, const float *height, int width, int height_px,
                                 int size, int gutter, pg_synth_faces *faces, pg_synth_exemplar *ex,
                                 pg_error *err);
pg_status pg_exemplar_torus_build(const float *albedo, const float *height, int size,
                                  pg_synth_faces *faces, pg_synth_exemplar *ex, pg_error *err);
void pg_synth_faces_free(pg_synth_faces *f);
/* Scale the height channel so its std is height_weight times the Lab std; sets
 * ex->lab_height_scale. */
void pg_exemplar_cube_weight_height(pg_synth_faces *f, double height_weight, pg_synth_exemplar *ex);

/* pg_gaussian_stack.c: in-place advance of one stack level: level s from level s-1
 * (a trous binomial filter with taps 2^(s-1) apart). tmp has the size of f->px. */
void pg_gaussian_stack_next(pg_synth_faces *f, int scale, float *tmp);

/* pg_appearance_pca.c: the raw 100-D Gaussian-weighted neighbourhood of texel (x, y)
 * of a face at spacing h; the weights; and the per-level analysis. */
void pg_appearance_gather(const pg_synth_faces *f, int face, int x, int y, int h, float *raw);
const float *pg_appearance_weights(void);
/* vals: the caller's scratch of nfaces * size^2 * PG_SYNTH_MAX_DIMS floats (one buffer
 * for every level: fresh pages cost a fault and the kernel's zeroing each). */
pg_status pg_appearance_pca_level(const pg_synth_faces *f, int scale, pg_synth_exemplar *ex,
                                  float *vals, pg_error *err);
/* Project one raw vector with the exemplar's basis at scale s into float comps[dims]. */
void pg_appearance_project(const pg_synth_exemplar *ex, int scale, const float *raw, float *comps);
/* The same on n raw vectors at once (comps: n x PG_SYNTH_MAX_DIMS), bit for bit. */
void pg_appearance_project_n(const pg_synth_exemplar *ex, int scale,
                             const float (*raw)[PG_SYNTH_RAW], int n, float *comps);
/* Gather and project the n texels (x.., y) of a face at scale s into comps
 * (n x PG_SYNTH_MAX_DIMS): the same bits as pg_appearance_gather and
 * pg_appearance_project on each, read straight from the rows where no read clamps. */
void pg_appearance_project_span(const pg_synth_faces *f, const pg_synth_exemplar *ex, int scale,
                                int face, int x, int y, int n, float *comps);

/* pg_kcoherence_patchmatch.c: fill ex->kcoh[scale]. dist: the caller's scratch of
 * nfaces * size^2 * (k - 1) int32 (may be the appearance's, once that is quantized). */
pg_status pg_kcoherence_build(pg_synth_exemplar *ex, int scale, uint64_t seed, int iters,
                              double min_separation, int32_t *dist, pg_error *err);

/* The k-coherence candidate of coordinate q from entry e of q's texel's table. An entry
 * is mostly an exemplar texel (orientation 0), but the lattice fill moves a lattice
 * point's match by up to 3 texels, and a move that crosses an exemplar seam carries
 * that seam's turn. The candidate is seen from the output through q's turn and then the
 * entry's, so the turns add (OR-ing them agreed only while one of the two was 0). */
static inline uint32_t pg_kcoherence_candidate(uint32_t q, uint32_t e) {
    return pg_synth_with_orient(e, pg_synth_orient(e) + pg_synth_orient(q));
}

/* pg_synth_cache.c */
uint64_t pg_synth_hash_bytes(uint64_t h, const void *data, size_t n);
pg_status pg_synth_cache_load(const char *path, uint64_t key, pg_synth_exemplar **out,
                              pg_error *err);
pg_status pg_synth_cache_save(const char *path, const pg_synth_exemplar *ex, pg_error *err);
pg_synth_exemplar *pg_synth_exemplar_alloc(int nfaces, int size, int levels, int dims, int k);

#endif
