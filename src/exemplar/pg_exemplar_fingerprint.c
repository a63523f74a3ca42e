/* pg_exemplar_fingerprint.c - who the exemplar's source files are, without reading them.
 *
 * Decoding Blue Marble and the 128 relief tiles and calibrating the relief takes about
 * two seconds; a prepared exemplar is found in the cache by a hash of the decoded pixels
 * (pg_synth.h). The fingerprint lets a warm run skip the decoding: it hashes what
 * pg_exemplar_load would read (each file's path, device, inode, size, modification and
 * change times, as make and git's index do) together with every loading option and the
 * library's source hash (PG_SOURCE_HASH), so other loading code, another file or a file
 * rewritten in place gives another fingerprint. The synthesis cache keeps a small index
 * from fingerprints to the content keys it has seen (docs/synthesis.md, "Exemplar
 * cache"); a fingerprint it has not seen costs the usual decoding, never a wrong
 * exemplar. */
#include "pg_marble.h"
#include "pg_source_hash.h"
#include "planetgen/pg_exemplar.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static uint64_t mix(uint64_t h, const void *data, size_t n) {
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3ULL; /* FNV-1a: the inputs are a few kB */
    return h;
}

static pg_status mix_file(uint64_t *h, const char *path, pg_error *err) {
    struct stat sb;
    if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
        return pg_error_set(err, PG_ERR_IO, "%s: not a readable file", path);
    int64_t id[8] = {(int64_t)sb.st_dev,          (int64_t)sb.st_ino,
                     (int64_t)sb.st_size,         (int64_t)sb.st_mtim.tv_sec,
                     (int64_t)sb.st_mtim.tv_nsec, (int64_t)sb.st_ctim.tv_sec,
                     (int64_t)sb.st_ctim.tv_nsec, 0};
    *h = mix(*h, path, strlen(path) + 1);
    *h = mix(*h, id, sizeof id);
    return PG_OK;
}

pg_status pg_exemplar_fingerprint(const pg_exemplar_opts *o, uint64_t *fp, char *albedo_src,
                                  char *height_src, size_t src_size, pg_error *err) {
    uint64_t h = 0xcbf29ce484222325ULL;
    const char *tag = "planetgen-exemplar-sources-v1 " PG_SOURCE_HASH;
    h = mix(h, tag, strlen(tag));
    double dbl[3] = {o->height_scale, o->height_offset, o->sea_level};
    uint64_t ints[3] = {o->max_pixels, (uint64_t)(int64_t)o->grid_width, o->repair_ocean};
    h = mix(h, dbl, sizeof dbl);
    h = mix(h, ints, sizeof ints);
    const char *apath = o->albedo_path ? o->albedo_path : PG_MARBLE_ALBEDO;
    snprintf(albedo_src, src_size, "%s", apath);
    pg_status st = mix_file(&h, apath, err);
    if (st == PG_OK && o->height_path) {
        snprintf(height_src, src_size, "%s", o->height_path);
        st = mix_file(&h, o->height_path, err);
    } else if (st == PG_OK) {
        const char *dir = o->relief_dir ? o->relief_dir : PG_MARBLE_RELIEF_DIR;
        snprintf(height_src, src_size, "%s (%dx%d tiles)", dir, PG_MARBLE_RELIEF_ROWS,
                 PG_MARBLE_RELIEF_COLS);
        for (int t = 0; st == PG_OK && t < PG_MARBLE_RELIEF_ROWS * PG_MARBLE_RELIEF_COLS; t++) {
            char path[1024];
            int r = t / PG_MARBLE_RELIEF_COLS, c = t % PG_MARBLE_RELIEF_COLS;
            snprintf(path, sizeof path, "%s/%06d/%06d_%06d.jpg", dir, r, r, c);
            st = mix_file(&h, path, err);
        }
    }
    *fp = h;
    return st;
}
