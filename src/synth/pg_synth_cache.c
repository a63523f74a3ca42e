/* pg_synth_cache.c - on-disk cache of prepared exemplars, and the exemplar's memory.
 *
 * A prepared exemplar is a few flat arrays; the cache file is a fixed header (magic,
 * format version, the key) and the scalars, followed by those arrays in a fixed order,
 * each at a 64-byte boundary. The key is a 64-bit hash of the input pixels, their sizes
 * and every preparation parameter, so a change of any of them misses the cache. Files
 * are written under a temporary name and renamed, so a crash never leaves a truncated
 * file under the real name; a file of another size or key is treated as a miss.
 *
 * A hit maps the file instead of reading it (docs/synthesis.md, "Exemplar cache"):
 * the arrays point into a private mapping, so loading costs the header and the page
 * table, and each page is read when the synthesis first touches it. Renaming a new
 * file over the old one leaves a mapping of the old one intact. */
#define _DEFAULT_SOURCE /* madvise(MADV_POPULATE_READ, MADV_DONTNEED) */
#include "pg_huge.h"
#include "pg_synth_internal.h"

#include <errno.h>
#include <stdbool.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define CACHE_MAGIC "PGSYNTH\x06" /* 5: 13-bit u, v; 6: arrays 64-byte aligned, mapped */

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
    ex->albedo = pg_huge_malloc(n * 3);
    ex->height = pg_huge_malloc(n * sizeof(float));
    int ok = ex->albedo && ex->height;
    for (int s = 0; s < levels && ok; s++) {
        /* not cleared: the preparation writes every entry, in parallel, so the threads
         * share the kernel's zeroing of the fresh pages instead of one memset */
        ex->app[s] = pg_huge_alloc(n * PG_SYNTH_MAX_DIMS * sizeof(int16_t));
        ex->kcoh[s] = k > 1 ? pg_huge_alloc(n * (k - 1) * sizeof(uint32_t)) : NULL;
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
    if (ex->map) {
        munmap(ex->map, ex->map_bytes); /* the arrays live in the mapping */
        free(ex);
        return;
    }
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

/* The arrays of the file in their order, each at a multiple of ALIGN bytes from the
 * start, so that a mapping of the file hands out arrays as aligned as allocated ones
 * (an appearance vector never straddles two cache lines). */
#define ALIGN 64
#define NPARTS (4 + 2 * PG_SYNTH_MAX_LEVELS)

typedef struct cache_part {
    void **slot; /* where the array's pointer lives in the exemplar (NULL: copied) */
    void *copy;  /* small arrays kept inside the struct */
    size_t offset, bytes;
} cache_part;

static size_t align_up(size_t v) {
    return (v + ALIGN - 1) / ALIGN * ALIGN;
}

/* The parts of ex's arrays and the file size; ex's sizes must be set. */
static int cache_layout(pg_synth_exemplar *ex, cache_part *parts, size_t *file_bytes) {
    size_t n = ntexels(ex), at = sizeof(cache_header) + sizeof(cache_scalars);
    int np = 0;
#define PART(slot_, copy_, bytes_)                                                                 \
    (parts[np].slot = (void **)(slot_), parts[np].copy = (copy_), at = align_up(at),               \
     parts[np].offset = at, parts[np].bytes = (bytes_), at += parts[np++].bytes)
    PART(&ex->albedo, NULL, n * 3);
    PART(&ex->height, NULL, n * sizeof(float));
    PART(NULL, ex->pca_basis, sizeof ex->pca_basis);
    for (int s = 0; s < ex->levels; s++) {
        PART(&ex->app[s], NULL, n * PG_SYNTH_MAX_DIMS * sizeof(int16_t));
        if (ex->k > 1) PART(&ex->kcoh[s], NULL, n * (size_t)(ex->k - 1) * 4);
    }
    PART(NULL, ex->pca_mean, sizeof ex->pca_mean);
#undef PART
    *file_bytes = at;
    return np;
}

static bool header_ok(const cache_header *h, uint64_t key) {
    return memcmp(h->magic, CACHE_MAGIC, 8) == 0 && h->key == key && h->levels >= 1 &&
           h->levels <= PG_SYNTH_MAX_LEVELS && h->size >= 1 && h->size <= PG_SYNTH_MAX_FACE_SIZE &&
           (h->nfaces == 1 || h->nfaces == 6) && h->dims >= 1 && h->dims <= PG_SYNTH_MAX_DIMS &&
           h->k >= 1 && h->k <= PG_SYNTH_MAX_K;
}

/* The exemplar of a mapped cache file: its scalars copied, its arrays pointing into the
 * mapping. Nothing is read here beyond the header: pages are faulted in when the
 * synthesis first reads them, so a level it never reads is never read from disk. */
static pg_synth_exemplar *from_map(void *map, size_t bytes, const cache_header *h) {
    pg_synth_exemplar *ex = calloc(1, sizeof *ex);
    if (!ex) return NULL;
    ex->nfaces = h->nfaces, ex->face_size = h->size, ex->levels = h->levels, ex->dims = h->dims,
    ex->k = h->k, ex->torus = h->torus != 0, ex->key = h->key;
    if (ex->nfaces == 6) {
        pg_error gerr = {0};
        if (pg_cube_grid_init(&ex->grid, PG_CUBE_DEFAULT_PROJECTION, 1, ex->face_size, &gerr)) {
            free(ex);
            return NULL;
        }
    }
    cache_part parts[NPARTS];
    size_t need;
    int np = cache_layout(ex, parts, &need);
    if (need != bytes) { /* truncated or foreign: a miss */
        free(ex);
        return NULL;
    }
    cache_scalars sc;
    memcpy(&sc, (const char *)map + sizeof *h, sizeof sc);
    ex->sea_level = sc.sea_level;
    ex->metres_to_app = sc.metres_to_app;
    ex->lab_height_scale = sc.lab_height_scale;
    ex->height_min = sc.height_min;
    ex->height_max = sc.height_max;
    ex->cold_seconds = sc.cold_seconds;
    memcpy(ex->app_scale, sc.app_scale, sizeof sc.app_scale);
    for (int i = 0; i < np; i++) {
        char *at = (char *)map + parts[i].offset;
        if (parts[i].slot)
            *parts[i].slot = at;
        else
            memcpy(parts[i].copy, at, parts[i].bytes);
    }
    ex->map = map;
    ex->map_bytes = bytes;
    return ex;
}

pg_status pg_synth_cache_load(const char *path, uint64_t key, pg_synth_exemplar **out,
                              pg_error *err) {
    (void)err;
    *out = NULL;
    int fd = open(path, O_RDONLY);
    if (fd < 0) return PG_OK; /* a miss */
    struct stat sb;
    cache_header h;
    void *map = MAP_FAILED;
    size_t bytes = 0;
    if (fstat(fd, &sb) == 0 && sb.st_size > (off_t)(sizeof h + sizeof(cache_scalars)) &&
        pread(fd, &h, sizeof h, 0) == (ssize_t)sizeof h && header_ok(&h, key)) {
        bytes = (size_t)sb.st_size;
        /* private and writable: a caller that writes gets its own copy of the page, the
         * file never changes */
        map = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE, fd, 0);
#ifdef MADV_POPULATE_READ
        /* the page table in one pass (~50 ms for 800 MB) rather than a fault per 64 kB
         * during the synthesis (~0.3 s); read, not write: a write populate would copy
         * every page of the private mapping */
        if (map != MAP_FAILED) madvise(map, bytes, MADV_POPULATE_READ);
#endif
    }
    close(fd); /* the mapping keeps the file */
    if (map == MAP_FAILED) return PG_OK;
    *out = from_map(map, bytes, &h);
    if (!*out) munmap(map, bytes);
    return PG_OK;
}

pg_status pg_synth_copy_level(const pg_synth_exemplar *ex, int scale, int16_t **app,
                              uint32_t **kcoh, pg_error *err) {
    *app = NULL;
    *kcoh = NULL;
    if (!ex->map || scale < 0 || scale >= ex->levels) return PG_OK;
    size_t n = ntexels(ex), ab = n * PG_SYNTH_MAX_DIMS * sizeof(int16_t),
           kb = ex->k > 1 ? n * (size_t)(ex->k - 1) * sizeof(uint32_t) : 0;
    *app = pg_huge_alloc(ab);
    *kcoh = kb ? pg_huge_alloc(kb) : NULL;
    if (!*app || (kb && !*kcoh)) {
        free(*app), free(*kcoh);
        *app = NULL, *kcoh = NULL;
        return pg_error_set(err, PG_ERR_NOMEM, "exemplar: out of memory for a level's tables");
    }
    /* in 2 MiB blocks, so that each thread faults in and fills its own huge pages */
    const size_t blk = (size_t)2 << 20;
    const char *src[2] = {(const char *)ex->app[scale], (const char *)ex->kcoh[scale]};
    char *dst[2] = {(char *)*app, (char *)*kcoh};
    const size_t len[2] = {ab, kb}, na = (ab + blk - 1) / blk, nk = (kb + blk - 1) / blk;
#pragma omp parallel for schedule(dynamic, 4)
    for (size_t b = 0; b < na + nk; b++) {
        int t = b >= na;
        size_t off = (t ? b - na : b) * blk, m = len[t] - off < blk ? len[t] - off : blk;
        memcpy(dst[t] + off, src[t] + off, m);
    }
    /* the copy replaces the mapped pages in memory instead of adding to it: drop them from
     * this process (they stay in the page cache; a later read maps them again) */
    const uintptr_t pg = (uintptr_t)sysconf(_SC_PAGESIZE);
    for (int t = 0; t < 2; t++) {
        uintptr_t lo = ((uintptr_t)src[t] + pg - 1) / pg * pg,
                  hi = ((uintptr_t)src[t] + len[t]) / pg * pg;
        if (len[t] && hi > lo) madvise((void *)lo, hi - lo, MADV_DONTNEED);
    }
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
    cache_part parts[NPARTS];
    size_t total;
    int np = cache_layout((pg_synth_exemplar *)ex, parts, &total);
    int bad = fwrite(&h, sizeof h, 1, f) != 1 || fwrite(&sc, sizeof sc, 1, f) != 1;
    size_t at = sizeof h + sizeof sc;
    static const char zeros[ALIGN] = {0};
    for (int i = 0; i < np && !bad; i++) {
        const void *src = parts[i].slot ? *parts[i].slot : parts[i].copy;
        bad = fwrite(zeros, 1, parts[i].offset - at, f) != parts[i].offset - at ||
              fwrite(src, 1, parts[i].bytes, f) != parts[i].bytes;
        at = parts[i].offset + parts[i].bytes;
    }
    if (fclose(f) != 0) bad = 1;
    if (bad || rename(tmp, path) != 0) {
        remove(tmp);
        return pg_error_set(err, PG_ERR_IO, "%s: cannot write cache file", path);
    }
    return PG_OK;
}
