/* pg_synth_prepare.c - exemplar preparation: the pipeline and its disk cache.
 *
 * cube reprojection (pg_exemplar_cube.c) -> per level s = 0..levels-1: Gaussian stack
 * level (pg_gaussian_stack.c) -> appearance vectors (pg_appearance_pca.c) -> k-coherence
 * table (pg_kcoherence_patchmatch.c). Only one float stack level is alive at a time;
 * what is kept is compact: sRGB8 albedo, float height, int16 appearance vectors and
 * packed candidate coordinates. The whole result is cached under a hash of the inputs
 * and parameters (pg_synth_cache.c). */
#include "pg_huge.h"
#include "pg_synth_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

double pg_synth_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

void pg_synth_exemplar_params_default(pg_synth_exemplar_params *p) {
    p->face_size = 512;
    p->dims = 8;
    p->levels = 6;
    p->k = 2;
    p->min_separation = 0.05;
    p->height_weight = 1.0;
    p->patchmatch_iters = 3;
    p->seed = 1;
}

float pg_synth_level_height(const pg_synth_exemplar *ex, int scale, uint32_t c) {
    int16_t q = ex->app[scale][pg_synth_texel(ex, c) * PG_SYNTH_MAX_DIMS];
    return q * ex->app_scale[scale] / ex->metres_to_app;
}

void pg_synth_default_cache_dir(char *buf, size_t size) {
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (xdg && *xdg)
        snprintf(buf, size, "%s/planetgen", xdg);
    else if (home && *home)
        snprintf(buf, size, "%s/.cache/planetgen", home);
    else
        snprintf(buf, size, "/tmp/planetgen-cache");
}

static int is_pow2(long v) {
    return v > 0 && (v & (v - 1)) == 0;
}

static pg_status check_params(const pg_synth_exemplar_params *p, pg_error *err) {
    if (!is_pow2(p->face_size) || p->face_size < 16 || p->face_size > PG_SYNTH_MAX_FACE_SIZE)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "exemplar face size %d: must be a power of two in 16..%d", p->face_size,
                            PG_SYNTH_MAX_FACE_SIZE);
    if (p->dims < 2 || p->dims > PG_SYNTH_MAX_DIMS)
        return pg_error_set(err, PG_ERR_BADINPUT, "appearance dims %d: must be in 2..%d", p->dims,
                            PG_SYNTH_MAX_DIMS);
    int maxl = 0;
    while ((2 << maxl) < p->face_size / 4 && maxl < PG_SYNTH_MAX_LEVELS)
        maxl++;
    if (p->levels < 1 || p->levels > maxl)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "analysed levels %d: must be in 1..%d for face size %d", p->levels,
                            maxl, p->face_size);
    if (p->k < 1 || p->k > PG_SYNTH_MAX_K)
        return pg_error_set(err, PG_ERR_BADINPUT, "k-coherence k = %d: must be in 1..%d", p->k,
                            PG_SYNTH_MAX_K);
    if (!(p->min_separation >= 0 && p->min_separation <= 0.5))
        return pg_error_set(err, PG_ERR_BADINPUT, "k-coherence separation %g: must be in [0, 0.5]",
                            p->min_separation);
    if (!(p->height_weight >= 0 && p->height_weight <= 1e3))
        return pg_error_set(err, PG_ERR_BADINPUT, "height weight %g: must be in [0, 1000]",
                            p->height_weight);
    return PG_OK;
}

static uint64_t make_key(const float *albedo, const float *height, int w, int h, float sea,
                         const pg_synth_exemplar_params *p, int torus) {
    uint64_t k = 0xcbf29ce484222325ULL;
    const char *tag = "planetgen-synth-exemplar-v4";
    k = pg_synth_hash_bytes(k, tag, strlen(tag));
    int32_t ints[9] = {
        w, h, torus, p->face_size, p->dims, p->levels, p->k, p->patchmatch_iters, (int32_t)p->seed};
    double dbl[3] = {p->min_separation, p->height_weight, sea};
    k = pg_synth_hash_bytes(k, ints, sizeof ints);
    k = pg_synth_hash_bytes(k, dbl, sizeof dbl);
    if (albedo) k = pg_synth_hash_bytes(k, albedo, (size_t)w * h * 3 * sizeof(float));
    if (height) k = pg_synth_hash_bytes(k, height, (size_t)w * h * sizeof(float));
    return k;
}

static pg_status mkdir_p(const char *dir, pg_error *err) {
    char buf[512];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *s = buf + 1; *s; s++)
        if (*s == '/') {
            *s = 0;
            mkdir(buf, 0755);
            *s = '/';
        }
    if (mkdir(buf, 0755) != 0 && errno != EEXIST)
        return pg_error_set(err, PG_ERR_IO, "--cache-dir %s: cannot create: %s", dir,
                            strerror(errno));
    return PG_OK;
}

static void height_range(pg_synth_exemplar *ex) {
    size_t n = (size_t)ex->nfaces * ex->face_size * ex->face_size;
    ex->height_min = ex->height_max = ex->height[0];
    for (size_t i = 1; i < n; i++) {
        if (ex->height[i] < ex->height_min) ex->height_min = ex->height[i];
        if (ex->height[i] > ex->height_max) ex->height_max = ex->height[i];
    }
}

static double exemplar_bytes(const pg_synth_exemplar *ex) {
    double n = (double)ex->nfaces * ex->face_size * ex->face_size;
    return n * (3 + 4) + ex->levels * n * (PG_SYNTH_MAX_DIMS * 2 + 4.0 * (ex->k - 1));
}

/* Stack, appearance and k-coherence for every analysed level. */
static pg_status analyse(pg_synth_faces *faces, const pg_synth_exemplar_params *p,
                         pg_synth_exemplar *ex, pg_synth_prep_info *info, pg_error *err) {
    float *tmp = pg_huge_malloc((size_t)faces->nfaces * faces->ext * faces->ext * PG_SYNTH_CH * 4);
    /* one scratch for every level's appearance vectors, then its k-coherence distances */
    _Static_assert(PG_SYNTH_MAX_K - 1 <= PG_SYNTH_MAX_DIMS, "the distances fit the scratch");
    float *scratch =
        pg_huge_malloc((size_t)faces->nfaces * faces->size * faces->size * PG_SYNTH_MAX_DIMS * 4);
    if (!tmp || !scratch) {
        free(tmp);
        free(scratch);
        return pg_error_set(err, PG_ERR_NOMEM, "exemplar: out of memory for the stack and scratch");
    }
    pg_status st = PG_OK;
    for (int s = 0; s < ex->levels && !st; s++) {
        double t0 = pg_synth_now();
        if (s > 0) pg_gaussian_stack_next(faces, s, tmp);
        double t1 = pg_synth_now();
        st = pg_appearance_pca_level(faces, s, ex, scratch, err);
        double t2 = pg_synth_now();
        if (!st)
            st = pg_kcoherence_build(ex, s, p->seed, p->patchmatch_iters, p->min_separation,
                                     (int32_t *)scratch, err);
        double t3 = pg_synth_now();
        info->stage_seconds[1] += t1 - t0;
        info->stage_seconds[2] += t2 - t1;
        info->stage_seconds[3] += t3 - t2;
    }
    free(tmp);
    free(scratch);
    return st;
}

static pg_status prepare(const float *albedo, const float *height, int w, int h, float sea,
                         const pg_synth_exemplar_params *p, const char *cache_dir, int torus,
                         pg_synth_exemplar **out, pg_synth_prep_info *info, pg_error *err) {
    double t0 = pg_synth_now();
    memset(info, 0, sizeof *info);
    *out = NULL;
    pg_status st = check_params(p, err);
    if (st) return st;
    uint64_t key = make_key(albedo, height, w, h, sea, p, torus);
    char dir[480];
    if (!cache_dir)
        pg_synth_default_cache_dir(dir, sizeof dir);
    else
        snprintf(dir, sizeof dir, "%s", cache_dir);
    if (dir[0]) {
        snprintf(info->cache_path, sizeof info->cache_path, "%s/exemplar-%016llx.pgsx", dir,
                 (unsigned long long)key);
        pg_synth_exemplar *cached = NULL;
        pg_synth_cache_load(info->cache_path, key, &cached, err);
        if (cached) {
            info->from_cache = true;
            info->seconds = pg_synth_now() - t0;
            info->bytes = exemplar_bytes(cached);
            *out = cached;
            return PG_OK;
        }
    }
    pg_synth_exemplar *ex =
        pg_synth_exemplar_alloc(torus ? 1 : 6, p->face_size, p->levels, p->dims, p->k);
    if (!ex) return pg_error_set(err, PG_ERR_NOMEM, "exemplar: out of memory");
    ex->key = key;
    ex->sea_level = sea;
    pg_synth_faces faces = {0};
    int gutter = torus ? 0 : 4 << (p->levels - 1);
    st = torus
             ? pg_exemplar_torus_build(albedo, height, p->face_size, &faces, ex, err)
             : pg_exemplar_cube_build(albedo, height, w, h, p->face_size, gutter, &faces, ex, err);
    info->stage_seconds[0] = pg_synth_now() - t0;
    if (!st) {
        height_range(ex);
        pg_exemplar_cube_weight_height(&faces, p->height_weight, ex);
        st = analyse(&faces, p, ex, info, err);
    }
    pg_synth_faces_free(&faces);
    if (st) {
        pg_synth_exemplar_free(ex);
        return st;
    }
    double tw = pg_synth_now();
    ex->cold_seconds = tw - t0;
    if (dir[0]) {
        pg_error werr = {0};
        if (mkdir_p(dir, &werr) != PG_OK || pg_synth_cache_save(info->cache_path, ex, &werr))
            info->cache_path[0] = 0; /* caching is an optimisation: never fatal */
    }
    info->stage_seconds[4] = pg_synth_now() - tw;
    info->seconds = pg_synth_now() - t0;
    info->bytes = exemplar_bytes(ex);
    *out = ex;
    return PG_OK;
}

/* ---- the index from source fingerprints to content keys ---- */

#define INDEX_MAGIC "PGSRCIX\x01"

static bool cache_dir_of(const char *cache_dir, char *dir, size_t size) {
    if (!cache_dir)
        pg_synth_default_cache_dir(dir, size);
    else
        snprintf(dir, size, "%s", cache_dir);
    return dir[0] != 0;
}

/* The index file of a source fingerprint under parameters p. */
static void index_path(char *buf, size_t size, const char *dir, uint64_t source_fp,
                       const pg_synth_exemplar_params *p) {
    uint64_t k = make_key(NULL, NULL, 0, 0, 0, p, 0);
    k = pg_synth_hash_bytes(k, &source_fp, sizeof source_fp);
    snprintf(buf, size, "%s/sources-%016llx.idx", dir, (unsigned long long)k);
}

pg_status pg_synth_lookup_exemplar(uint64_t source_fp, const pg_synth_exemplar_params *p,
                                   const char *cache_dir, pg_synth_exemplar **out,
                                   pg_synth_prep_info *info, pg_error *err) {
    double t0 = pg_synth_now();
    memset(info, 0, sizeof *info);
    *out = NULL;
    pg_status st = check_params(p, err);
    char dir[480], idx[560];
    if (st || !cache_dir_of(cache_dir, dir, sizeof dir)) return st;
    index_path(idx, sizeof idx, dir, source_fp, p);
    FILE *f = fopen(idx, "rb");
    char magic[8];
    uint64_t key = 0;
    bool ok = f && fread(magic, 8, 1, f) == 1 && !memcmp(magic, INDEX_MAGIC, 8) &&
              fread(&key, sizeof key, 1, f) == 1;
    if (f) fclose(f);
    if (!ok) return PG_OK; /* a miss */
    snprintf(info->cache_path, sizeof info->cache_path, "%s/exemplar-%016llx.pgsx", dir,
             (unsigned long long)key);
    st = pg_synth_cache_load(info->cache_path, key, out, err);
    if (st || !*out) return st;
    info->from_cache = true;
    info->seconds = pg_synth_now() - t0;
    info->bytes = exemplar_bytes(*out);
    return PG_OK;
}

void pg_synth_remember_sources(uint64_t source_fp, const pg_synth_exemplar_params *p,
                               const char *cache_dir, const pg_synth_exemplar *ex) {
    char dir[480], idx[560], tmp[600];
    if (!cache_dir_of(cache_dir, dir, sizeof dir)) return;
    index_path(idx, sizeof idx, dir, source_fp, p);
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", idx, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) return; /* caching is an optimisation: never fatal */
    bool bad = fwrite(INDEX_MAGIC, 8, 1, f) != 1 || fwrite(&ex->key, sizeof ex->key, 1, f) != 1;
    if (fclose(f) != 0 || bad || rename(tmp, idx) != 0) remove(tmp);
}

pg_status pg_synth_prepare_exemplar(const float *albedo, const float *height, int width,
                                    int height_px, float sea_level,
                                    const pg_synth_exemplar_params *p, const char *cache_dir,
                                    pg_synth_exemplar **out, pg_synth_prep_info *info,
                                    pg_error *err) {
    if (!albedo || !height || width < 2 || height_px < 1 || width != 2 * height_px)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "exemplar: equirectangular maps must be 2:1 (got %d x %d)", width,
                            height_px);
    return prepare(albedo, height, width, height_px, sea_level, p, cache_dir, 0, out, info, err);
}

pg_status pg_synth_prepare_torus(const float *albedo, const float *height, int size,
                                 float sea_level, const pg_synth_exemplar_params *p,
                                 const char *cache_dir, pg_synth_exemplar **out,
                                 pg_synth_prep_info *info, pg_error *err) {
    if (size != p->face_size)
        return pg_error_set(err, PG_ERR_BADINPUT, "toroidal exemplar: size %d != face size %d",
                            size, p->face_size);
    return prepare(albedo, height, size, size, sea_level, p, cache_dir, 1, out, info, err);
}
