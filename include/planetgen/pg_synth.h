/* pg_synth.h - exemplar analysis and Lefebvre-Hoppe texture synthesis of terrain.
 *
 * Two halves:
 *  1. Exemplar preparation (pg_synth_prepare_*): the global albedo + height maps are
 *     reprojected onto an "exemplar cube" (6 faces of E x E texels, with gutters taken
 *     from the sphere itself so neighbourhoods near face edges are valid), filtered into
 *     a Gaussian stack (Lefebvre & Hoppe 2005), summarised per texel and per level by an
 *     8-D appearance vector (Lefebvre & Hoppe 2006; component 1 = local mean height as in
 *     Gain et al. 2015), and indexed by a k-coherence table built with PatchMatch
 *     (Barnes et al. 2009). The result is cached on disk under a hash of inputs+params.
 *  2. Synthesis: every output texel stores a packed exemplar coordinate (face, u, v)
 *     and a height offset V in metres. Levels go coarse to fine: upsample, jitter,
 *     then c correction passes of 4 sub-passes each. The per-level operations work on
 *     a *view* (a rectangle of a level with a one-texel halo of read-only neighbour
 *     texels), so a planet can run them per tile with halos gathered across tile edges
 *     and cube seams, and pit removal can edit V between passes.
 *
 * Levels are named by their "scale" s: exemplar spacing h = 2^s, s = 0 finest. All
 * randomness is a hash of (seed, scale, face, global x, global y): results do not
 * depend on tiling or thread count. */
#ifndef PLANETGEN_PG_SYNTH_H
#define PLANETGEN_PG_SYNTH_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_cube.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PG_SYNTH_MAX_DIMS 8    /* appearance components stored per texel */
#define PG_SYNTH_MAX_LEVELS 10 /* corrected (analysed) levels */
#define PG_SYNTH_MAX_K 4       /* k-coherence candidates, including the texel itself */

/* ---- packed exemplar coordinates: face in bits 28..30, orientation in 26..27, v in
 * 13..25, u in 0..12 ----
 * The orientation o is the number of quarter turns (pg_synth_orient_apply) that take an
 * offset in the output's frame into the frame of the coordinate's exemplar face. It is
 * 0 where synthesis starts; a move that crosses an exemplar seam adds that seam's turn,
 * and a coordinate handed across an output seam adds the output seam's turn. So a patch
 * keeps its orientation wherever it continues, which translations alone cannot do on a
 * cube whose face frames are turned against each other. The exemplar's own tables
 * (k-coherence) hold o = 0. */
#define PG_SYNTH_COORD_BITS 13
#define PG_SYNTH_MAX_FACE_SIZE (1 << PG_SYNTH_COORD_BITS)
#define PG_SYNTH_ORIENT_MASK 0x0c000000u
static inline uint32_t pg_synth_pack(int face, int u, int v) {
    return ((uint32_t)face << 28) | ((uint32_t)v << 13) | (uint32_t)u;
}
static inline int pg_synth_face(uint32_t c) {
    return (int)((c >> 28) & 7u);
}
static inline int pg_synth_v(uint32_t c) {
    return (int)((c >> 13) & 0x1fffu);
}
static inline int pg_synth_u(uint32_t c) {
    return (int)(c & 0x1fffu);
}
static inline int pg_synth_orient(uint32_t c) {
    return (int)((c >> 26) & 3u);
}
static inline uint32_t pg_synth_with_orient(uint32_t c, int o) {
    return (c & ~PG_SYNTH_ORIENT_MASK) | ((uint32_t)(o & 3) << 26);
}

typedef struct pg_synth_exemplar_params {
    int face_size;         /* E, power of two >= 16; default 512 */
    int dims;              /* appearance components d, 2..8; default 8 */
    int levels;            /* analysed (corrected) levels, scales 0..levels-1; default 6 */
    int k;                 /* k-coherence candidates per texel incl. itself; default 2 */
    double min_separation; /* k-coherence: other candidates at least this * E away; 0.05 */
    double height_weight;  /* w_h: height std relative to the Lab albedo std; default 1 */
    int patchmatch_iters;  /* default 5 */
    uint64_t seed;         /* PatchMatch randomness; default 1 */
} pg_synth_exemplar_params;

void pg_synth_exemplar_params_default(pg_synth_exemplar_params *p);

/* A prepared exemplar. Read-only after preparation; safe to share between threads. */
typedef struct pg_synth_exemplar {
    int face_size, nfaces; /* nfaces = 6 (cube) or 1 (a toroidal test exemplar) */
    bool torus;            /* coordinates wrap modulo E (else cross onto the next face) */
    int levels, dims, k;
    float sea_level;                      /* metres */
    float metres_to_app;                  /* appearance units of component 1 per metre of height */
    float app_scale[PG_SYNTH_MAX_LEVELS]; /* float appearance = int16 value * app_scale */
    uint8_t *albedo;                      /* nfaces*E*E*3, sRGB 8-bit, finest level */
    float *height;                        /* nfaces*E*E metres, finest level */
    int16_t *app[PG_SYNTH_MAX_LEVELS];    /* nfaces*E*E*PG_SYNTH_MAX_DIMS per scale */
    uint32_t *kcoh[PG_SYNTH_MAX_LEVELS];  /* nfaces*E*E*(k-1) packed coords per scale */
    float pca_basis[PG_SYNTH_MAX_LEVELS][PG_SYNTH_MAX_DIMS][100]; /* row 0: unit vector of
                                                                   * component 1 (local mean
                                                                   * height); rows 1..d-1: PCA
                                                                   * axes; over the 100 raw
                                                                   * dims (25 samples x Lab+h) */
    float pca_mean[PG_SYNTH_MAX_LEVELS][100];
    float lab_height_scale; /* height channel = metres * this (before Gaussian weights) */
    float height_min, height_max;
    uint64_t key;        /* cache key */
    double cold_seconds; /* wall time the (uncached) preparation took, kept in the cache */
    pg_cube_grid grid;   /* 1 tile of E per face: wraps coordinates across exemplar seams */
    /* Loaded from the cache: albedo, height, app and kcoh point into this read-only
     * mapping of the cache file (pg_synth_exemplar_free unmaps it); NULL when they were
     * allocated. */
    void *map;
    size_t map_bytes;
} pg_synth_exemplar;

typedef struct pg_synth_prep_info {
    double seconds; /* wall time of this preparation (cold or cached) */
    bool from_cache;
    char cache_path[512];    /* "" when caching is off */
    double bytes;            /* memory held by the prepared exemplar */
    double stage_seconds[5]; /* cube (with the check of the parameters and the key's
                                hash of the inputs), stack, pca (with the height range
                                and weighting), kcoherence, cache write */
} pg_synth_prep_info;

/* Prepare from a global equirectangular albedo (RGB 0..1, sRGB) and height (metres)
 * on one common grid, width == 2 * height_px (row 0 north). cache_dir: NULL = default
 * ($XDG_CACHE_HOME/planetgen or ~/.cache/planetgen), "" = no cache. */
pg_status pg_synth_prepare_exemplar(const float *albedo, const float *height, int width,
                                    int height_px, float sea_level,
                                    const pg_synth_exemplar_params *p, const char *cache_dir,
                                    pg_synth_exemplar **out, pg_synth_prep_info *info,
                                    pg_error *err);

/* Prepare a single toroidal face from a size x size tile (size == p->face_size). */
pg_status pg_synth_prepare_torus(const float *albedo, const float *height, int size,
                                 float sea_level, const pg_synth_exemplar_params *p,
                                 const char *cache_dir, pg_synth_exemplar **out,
                                 pg_synth_prep_info *info, pg_error *err);

/* The cached exemplar prepared from the sources whose fingerprint is source_fp
 * (pg_exemplar_fingerprint) under parameters p, found through the cache's index without
 * the sources' pixels; *out is NULL on a miss (then load the sources, prepare with
 * pg_synth_prepare_exemplar and record the pair with pg_synth_remember_sources). */
pg_status pg_synth_lookup_exemplar(uint64_t source_fp, const pg_synth_exemplar_params *p,
                                   const char *cache_dir, pg_synth_exemplar **out,
                                   pg_synth_prep_info *info, pg_error *err);
/* Record in the cache's index that source_fp under p prepares ex (whose cache file
 * pg_synth_prepare_exemplar wrote). Best effort: a failure only costs a later miss. */
void pg_synth_remember_sources(uint64_t source_fp, const pg_synth_exemplar_params *p,
                               const char *cache_dir, const pg_synth_exemplar *ex);

void pg_synth_exemplar_free(pg_synth_exemplar *ex);

/* Private copies of the appearance and k-coherence tables of level `scale` of an
 * exemplar mapped from the cache (ex->map), on transparent huge pages where the kernel
 * allows, for a caller about to read that level densely: through the mapping's 4 KiB
 * pages the synthesis spends about 12% more CPU on TLB misses. The level's mapped pages
 * are then dropped from the process (they stay in the page cache and come back when
 * read), so the copies take their place in memory. *app and *kcoh are NULL when ex is
 * not mapped (read its own tables); the caller frees them with free(). */
pg_status pg_synth_copy_level(const pg_synth_exemplar *ex, int scale, int16_t **app,
                              uint32_t **kcoh, pg_error *err);

/* The default cache directory (no trailing slash) into buf. */
void pg_synth_default_cache_dir(char *buf, size_t size);

/* Exemplar lookups. */
static inline size_t pg_synth_texel(const pg_synth_exemplar *ex, uint32_t c) {
    return ((size_t)pg_synth_face(c) * (size_t)ex->face_size + (size_t)pg_synth_v(c)) *
               (size_t)ex->face_size +
           (size_t)pg_synth_u(c);
}
/* Local mean height (metres) of the exemplar at coordinate c and scale s: the
 * level's height E_s, used to reconstruct R = E_s(S) + V for pit removal. */
float pg_synth_level_height(const pg_synth_exemplar *ex, int scale, uint32_t c);

/* Move coordinate c by (du, dv) texels of the output's frame (turned by c's orientation
 * into its exemplar face's frame): wraps on a torus; on the cube, a move past a face edge
 * continues on the neighbouring face (pg_cube_wrap) and adds that seam's turn to the
 * orientation, so coordinates never pile up at an edge. |du|, |dv| < E. */
uint32_t pg_synth_offset(const pg_synth_exemplar *ex, uint32_t c, int du, int dv);

/* ---------------------------------- synthesis ---------------------------------- */

typedef struct pg_synth_params {
    uint64_t seed;
    double jitter;                                /* r_l for every level, in [0,1]; default 0.4 */
    double jitter_level[PG_SYNTH_MAX_LEVELS + 8]; /* per-scale override; <0 = use jitter */
    int passes;                                   /* correction passes c per level; default 2 */
    double kappa;          /* jump penalty: k-coherence candidates cost * (1 + kappa); 0.1 */
    bool height_offsets;   /* Gain et al. offsets V; default true */
    double offset_penalty; /* lambda: an offset h costs lambda*4*h^2; 0 = Gain; default 1 */
    int tile_size;         /* flat driver: correction tile size (0 = whole level) */
    /* cube synthesis near the cube's corners: a candidate costs * (1 + grid_shape s d), d
     * how far its exemplar texel's grid shape is from the output texel's, s from 0 where
     * either face coordinate is within half a half-width of the centre to 1 at a corner,
     * fading out over the 4 texels before a face edge. 0 = off, pg_synth_params_default's
     * value; the planet synthesis's default is PG_PLANET_GRID_SHAPE (docs/synthesis.md,
     * "Grid shape at the cube's corners") */
    double grid_shape;
} pg_synth_params;

void pg_synth_params_default(pg_synth_params *p);

/* A rectangle of one synthesis level with a one-texel halo. S and V point at the
 * top-left interior texel; texel (x, y) for x, y in [-1, w] x [-1, h] is at
 * S[y * stride + x]. Halo texels are read, never written. orient (may be NULL)
 * gives, per texel (same indexing), the number of quarter turns counter-clockwise,
 * 0..3, that maps an offset in this view's frame to that texel's frame (non-zero only
 * across a cube seam). Only turns: a coordinate carries 2 bits of turn and no mirror, so
 * a mirrored value (4..7, which pg_synth_orient_apply accepts) would lose its mirror in
 * the moved coordinate. The cube's seams never mirror. */
typedef struct pg_synth_view {
    uint32_t *S;
    float *V;
    const uint8_t *orient;
    ptrdiff_t stride;
    int w, h;
    int face;    /* output face (for hashing); 0 for a flat region */
    long gx, gy; /* global position of interior texel (0,0) at this level */
    int face_r;  /* texels along a cube face's edge at this level; 0: not a cube face */
} pg_synth_view;

/* Apply dihedral transform o to an offset (dx, dy). */
void pg_synth_orient_apply(int o, int *dx, int *dy);

/* Coordinate of view texel i moved by (dx, dy) texels of the view's frame, expressed
 * in the view's frame: the texel's seam orientation turns the offset into its own
 * frame, and is added to the result's orientation (a halo texel's coordinate is
 * oriented for the neighbouring face). */
uint32_t pg_synth_view_move(const pg_synth_exemplar *ex, const pg_synth_view *v, ptrdiff_t i,
                            int dx, int dy);

/* Uniform hash in [0, 2^32) of (seed, scale, face, x, y, salt). */
uint32_t pg_synth_hash(uint64_t seed, int scale, int face, long x, long y, int salt);

/* Children of parent texel (x, y) at scale s+1: child (2x+dx, 2y+dy) at scale s gets
 * S + floor(h_s (d - 1/2)) and the parent's V. child's interior must be 2x parent's. */
void pg_synth_upsample(const pg_synth_exemplar *ex, int scale, const pg_synth_view *parent,
                       pg_synth_view *child);

/* S += floor(h_s * H(p) * r + 1/2) on the interior (r = jitter strength for scale s). */
void pg_synth_jitter(const pg_synth_exemplar *ex, int scale, double r, uint64_t seed,
                     pg_synth_view *v);

/* One correction sub-pass on the interior texels whose global (x, y) parity is
 * (parity & 1, parity >> 1). Requires scale < ex->levels. Reads only the halo and the
 * texels of other parities, so the result does not depend on the order of texels,
 * tiles or threads. */
void pg_synth_correct_subpass(const pg_synth_exemplar *ex, int scale, const pg_synth_params *p,
                              int parity, pg_synth_view *v);

/* Sub-pass order used by the drivers. */
extern const int pg_synth_subpass_order[4];

/* Effective jitter strength for a scale. */
double pg_synth_jitter_for(const pg_synth_params *p, int scale);

/* ---- flat-region driver ---- */

typedef struct pg_synth_result {
    int size;         /* N */
    uint32_t *coords; /* N*N packed exemplar coordinates, row-major */
    float *offset;    /* N*N height offsets V (metres) */
    double level_seconds[PG_SYNTH_MAX_LEVELS + 8];
    int nlevels_run;
} pg_synth_result;

/* Hook run after every correction pass (e.g. pit removal editing V). S and V cover a
 * res x res level with a one-texel border; stride = res + 2. */
typedef void (*pg_synth_pass_hook)(void *user, const pg_synth_exemplar *ex, int scale, int pass,
                                   uint32_t *S, float *V, int res, ptrdiff_t stride);

/* Bytes the flat driver needs for an N x N output (beyond the exemplar). */
double pg_synth_flat_bytes(int n);

/* Synthesize an N x N flat region (N a power of two). */
pg_status pg_synth_flat(const pg_synth_exemplar *ex, int n, const pg_synth_params *p,
                        pg_synth_pass_hook hook, void *hook_user, pg_synth_result *out,
                        pg_error *err);

void pg_synth_result_free(pg_synth_result *r);

/* albedo = E_rgb(S) (sRGB 8-bit, 3 per texel) and height = E_h(S) + V (metres), for
 * count texels. Either output may be NULL. */
void pg_synth_render(const pg_synth_exemplar *ex, const uint32_t *coords, const float *offset,
                     size_t count, uint8_t *albedo_rgb, float *height_m);

/* Debug colouring of coordinates: red = u/E, green = v/E, blue = face/(nfaces). */
void pg_synth_coords_rgb(const pg_synth_exemplar *ex, const uint32_t *coords, size_t count,
                         uint8_t *rgb);

/* Monotonic wall clock in seconds (for timings in reports and benches). */
double pg_synth_now(void);

#ifdef __cplusplus
}
#endif

#endif
