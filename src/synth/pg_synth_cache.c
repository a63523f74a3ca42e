/* pg_synth_cache.c - on-disk cache of prepared exemplars, and the exemplar's memory.
 *
 * A prepared exemplar is a few flat arrays; the cache file is a fixed header (magic,
 * format version, the key) followed by those arrays in a fixed order. The key is a
 * 64-bit hash of the input pixels, their sizes and every preparation parameter, so a
 * change of any of them misses the cache. Files are written under a temporary name
 * and renamed, so a crash never leaves a truncated file under the real name; a file
 * that fails to read completely or has another key is treated as a miss. */
#define _DEFAULT_SOURCE /* madvise(MADV_HUGEPAGE) */
#include "pg_synth_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#define CACHE_MAGIC "PGSYNTH\x05" /* 5: 13-bit u, v */

/* FNV-1a over 8-byte words with a final avalanche; fast enough for ~60 MB inputs. */
uint64_t pg_synth_hash_bytes(uint64_t h, const void *data, size_t n) {
    const unsigned char *p = data;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        h = (h ^ w) * 0x100000001b3ULL;
        h ^= h >> 29;
    }
    for (; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3ULL;
    return h;
}

static size_t ntexels(const pg_synth_exemplar *ex) {
    return (size_t)ex->nfaces * ex->face_size * ex->face_size;
}

/* Large random-access tables live on transparent huge pages where the kernel allows
 * (madvise mode): synthesis reads them at random and is otherwise bound by TLB misses. */
static void *alloc_table(size_t bytes) {
    const size_t huge = (size_t)2 << 20;
    size_t rounded = (bytes + huge - 1) / huge * huge;
    void *p = aligned_alloc(huge, rounded);
    if (!p) return NULL;
#ifdef MADV_HUGEPAGE
    madvise(p, rounded, MADV_HUGEPAGE);
#endif
    memset(p, 0, bytes);
    return p;
}

pg_synth_exemplar *pg_synth_exemplar_alloc(int nfaces, int size, int levels, int dims, int k) {
    pg_synth_exemplar *ex = calloc(1, sizeof *ex);
    if (!ex) return NULL;
    ex->nfaces = nfaces;
    ex->face_size = size;
    ex->torus = nfaces == 1;
    ex->levels = levels;
    ex->dims = dims;
    ex->k = k;
    size_t n = ntexels(ex);
    if (nfaces == 6) {
        pg_error gerr = {0};
        if (pg_cube_grid_init(&ex->grid, PG_CUBE_DEFAULT_PROJECTION, 1, size, &gerr) != PG_OK) {
            free(ex);
            return NULL;
        }
    }
    ex->albedo = malloc(n * 3);
    ex->height = malloc(n * sizeof(float));
    int ok = ex->albedo && ex->height;
    for (int s = 0; s < levels && ok; s++) {
        ex->app[s] = alloc_table(n * PG_SYNTH_MAX_DIMS * sizeof(int16_t));
        ex->kcoh[s] = k > 1 ? alloc_table(n * (k - 1) * sizeof(uint32_t)) : NULL;
        ok = ex->app[s] && (k <= 1 || ex->kcoh[s]);
    }
    if (!ok) {
        pg_synth_exemplar_free(ex);
        return NULL;
    }
    return ex;
}

void pg_synth_exemplar_free(pg_synth_exemplar *ex) {
    if (!ex) return;
    free(ex->albedo);
    free(ex->height);
    for (int s = 0; s < PG_SYNTH_MAX_LEVELS; s++) {
        free(ex->app[s]);
        free(ex->kcoh[s]);
    }
    free(ex);
}

typedef struct cache_header {
    char magic[8];
    uint64_t key;
    int32_t nfaces, size, levels, dims, k, torus;
} cache_header;

/* The scalar part of the exemplar that follows the header: everything in the struct
 * before the pointers is plain data. */
typedef struct cache_scalars {
    float sea_level, metres_to_app, lab_height_scale, height_min, height_max;
    float app_scale[PG_SYNTH_MAX_LEVELS];
    double cold_seconds;
} cache_scalars;

static int io_arrays(pg_synth_exemplar *ex, FILE *f, int writing) {
    size_t n = ntexels(ex);
    struct {
        void *p;
        size_t bytes;
    } parts[3 + 2 * PG_SYNTH_MAX_LEVELS];
    int np = 0;
    parts[np].p = ex->albedo, parts[np++].bytes = n * 3;
    parts[np].p = ex->height, parts[np++].bytes = n * sizeof(float);
    parts[np].p = ex->pca_basis, parts[np++].bytes = sizeof ex->pca_basis;
    for (int s = 0; s < ex->levels; s++) {
        parts[np].p = ex->app[s], parts[np++].bytes = n * PG_SYNTH_MAX_DIMS * sizeof(int16_t);
        if (ex->k > 1) parts[np].p = ex->kcoh[s], parts[np++].bytes = n * (ex->k - 1) * 4;
    }
    for (int i = 0; i < np; i++) {
        size_t done = writing ? fwrite(parts[i].p, 1, parts[i].bytes, f)
                              : fread(parts[i].p, 1, parts[i].bytes, f);
        if (done != parts[i].bytes) return -1;
    }
    if (writing ? fwrite(ex->pca_mean, sizeof ex->pca_mean, 1, f) != 1
                : fread(ex->pca_mean, sizeof ex->pca_mean, 1, f) != 1)
        return -1;
    return 0;
}

pg_status pg_synth_cache_load(const char *path, uint64_t key, pg_synth_exemplar **out,
                              pg_error *err) {
    (void)err;
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return PG_OK; /* a miss */
    cache_header h;
    cache_scalars sc;
    pg_synth_exemplar *ex = NULL;
    if (fread(&h, sizeof h, 1, f) == 1 && memcmp(h.magic, CACHE_MAGIC, 8) == 0 && h.key == key &&
        fread(&sc, sizeof sc, 1, f) == 1 && h.levels >= 1 && h.levels <= PG_SYNTH_MAX_LEVELS &&
        h.size >= 1 && h.size <= PG_SYNTH_MAX_FACE_SIZE)
        ex = pg_synth_exemplar_alloc(h.nfaces, h.size, h.levels, h.dims, h.k);
    if (ex) {
        ex->torus = h.torus != 0;
        ex->key = key;
        ex->sea_level = sc.sea_level;
        ex->metres_to_app = sc.metres_to_app;
        ex->lab_height_scale = sc.lab_height_scale;
        ex->height_min = sc.height_min;
        ex->height_max = sc.height_max;
        ex->cold_seconds = sc.cold_seconds;
        memcpy(ex->app_scale, sc.app_scale, sizeof sc.app_scale);
        if (io_arrays(ex, f, 0) != 0) {
            pg_synth_exemplar_free(ex);
            ex = NULL;
        }
    }
    fclose(f);
    *out = ex;
    return PG_OK;
}

pg_status pg_synth_cache_save(const char *path, const pg_synth_exemplar *ex, pg_error *err) {
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) return pg_error_set(err, PG_ERR_IO, "%s: cannot write cache: %s", tmp, strerror(errno));
    cache_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, CACHE_MAGIC, 8);
    h.key = ex->key;
    h.nfaces = ex->nfaces, h.size = ex->face_size, h.levels = ex->levels, h.dims = ex->dims,
    h.k = ex->k, h.torus = ex->torus;
    cache_scalars sc = {ex->sea_level,   ex->metres_to_app, ex->lab_height_scale,
                        ex->height_min,  ex->height_max,    {0},
                        ex->cold_seconds};
    memcpy(sc.app_scale, ex->app_scale, sizeof sc.app_scale);
    int bad = fwrite(&h, sizeof h, 1, f) != 1 || fwrite(&sc, sizeof sc, 1, f) != 1 ||
              io_arrays((pg_synth_exemplar *)ex, f, 1) != 0;
    if (fclose(f) != 0) bad = 1;
    if (bad || rename(tmp, path) != 0) {
        remove(tmp);
        return pg_error_set(err, PG_ERR_IO, "%s: cannot write cache file", path);
    }
    return PG_OK;
}
