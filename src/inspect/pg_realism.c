/* pg_realism.c - the realism report of one side, planet or Earth (pg_realism.h).
 *
 * The design: one routine measures any planet; Earth is just another planet, the
 * exemplar reprojected onto a cube of the same geometry with the identity coordinate
 * map. So every figure is computed by the same code on both sides and the report can
 * print them side by side. Only the comparisons between sides (hypsometry W1, zonal
 * correlation) take the other side's result as input.
 *
 * Drainage is measured on pit-free heights: a Priority-Flood fill with epsilon
 * (pg_pits, Barnes et al. 2014) runs on a copy first. A planet whose final pass
 * already removed every pit comes back unchanged from it up to the epsilon gradients
 * on flats, so its figures are those of the planet as delivered; Earth's raw relief,
 * which has tens of thousands of closed basins, gets the same treatment the planet's
 * final pass gave the planet.
 *
 * The Earth cache is the struct itself, written raw behind a magic, a key and its
 * size: it holds no pointers. The key hashes the exemplar's data, the geometry and the
 * library's source hash, so a cache is read only by code identical to the code that
 * wrote it. */
#include "planetgen/pg_realism.h"
#include "planetgen/pg_synth.h"

#include "pg_source_hash.h"
#include "pg_synth_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const stage_names[PG_REALISM_NSTAGES] = {
    "distortion",     "seams",    "copy detection", "neighbourhood fidelity",
    "Earth-likeness", "drainage", "depressions"};

const char *pg_realism_stage_name(int stage) {
    return stage >= 0 && stage < PG_REALISM_NSTAGES ? stage_names[stage] : "?";
}

typedef struct stage_clock {
    pg_realism_progress_fn fn;
    void *user;
    pg_realism *out;
    int stage;
    double t0;
} stage_clock;

static void begin(stage_clock *c, int stage) {
    c->stage = stage;
    c->t0 = pg_synth_now();
    if (c->fn) c->fn(c->user, stage, true);
}

static void end(stage_clock *c) {
    c->out->seconds[c->stage] += pg_synth_now() - c->t0;
    if (c->fn) c->fn(c->user, c->stage, false);
}

/* ---- the stages ---- */

static pg_status distortion(const pg_planet *p, pg_realism *out, pg_inspect_distortion *keep,
                            pg_error *err) {
    pg_inspect_distortion *d = malloc(sizeof *d);
    if (!d) return pg_error_set(err, PG_ERR_NOMEM, "inspect: out of memory");
    pg_status st = pg_inspect_distortion_compute(p, d, err);
    if (st == PG_OK) {
        out->pole_distortion_ratio = d->ratio;
        out->distortion_share_ratio = d->share_ratio;
        out->distortion_reference = d->reference;
        out->distortion_worst_figure = d->worst_figure;
        snprintf(out->distortion_worst_view, sizeof out->distortion_worst_view, "%s",
                 d->worst_name ? d->worst_name : "");
        if (keep) *keep = *d;
    }
    free(d);
    return st;
}

static void compare(pg_realism *out, const pg_realism *other) {
    if (!other) {
        out->hypsometry_w1_land_m = out->hypsometry_w1_ocean_m = out->hypsometry_w1_m = NAN;
        out->zonal_correlation = NAN;
        for (int t = 0; t < PG_TYPE_COUNT; t++)
            out->zonal_correlation_per_type[t] = NAN;
        return;
    }
    pg_earthlike_w1(&out->earthlike, &other->earthlike, &out->hypsometry_w1_land_m,
                    &out->hypsometry_w1_ocean_m);
    out->hypsometry_w1_m = fmax(out->hypsometry_w1_land_m, out->hypsometry_w1_ocean_m);
    out->zonal_correlation = pg_earthlike_zonal_correlation(&out->earthlike, &other->earthlike,
                                                            out->zonal_correlation_per_type);
}

/* Everything but drainage and depressions, for either side. */
static pg_status measure_surface(const pg_planet *p, const pg_exemplar *ex,
                                 const pg_inspect_fid_exemplar *fx, stage_clock *c,
                                 pg_inspect_distortion *keep, pg_error *err) {
    pg_realism *out = c->out;
    begin(c, PG_REALISM_DISTORTION);
    pg_status st = distortion(p, out, keep, err);
    end(c);
    if (st != PG_OK) return st;
    begin(c, PG_REALISM_SEAMS);
    st = pg_inspect_seams_compute(p, &out->seams, err);
    if (st == PG_OK) st = pg_inspect_copy_coherence(p, &out->coherence, err);
    end(c);
    if (st != PG_OK) return st;
    begin(c, PG_REALISM_COPY);
    st = pg_inspect_copy_fraction(p, &out->copy, err);
    end(c);
    if (st != PG_OK) return st;
    begin(c, PG_REALISM_FIDELITY);
    st = fx ? pg_inspect_fidelity_with(p, fx, &out->fidelity, err)
            : pg_inspect_fidelity_compute(p, ex, &out->fidelity, err);
    end(c);
    if (st != PG_OK) return st;
    begin(c, PG_REALISM_EARTHLIKE);
    st = pg_earthlike_compute(p, &out->earthlike, err);
    if (st == PG_OK) st = pg_earthlike_novelty_compute(p, ex, &out->novelty, err);
    end(c);
    return st;
}

/* p's heights with every pit filled (epsilon: every land texel drains), 6*n*n. */
static pg_status filled_heights(const pg_planet *p, float **out, pg_error *err) {
    pg_pits_topo t;
    pg_status st = pg_pits_topo_cube(&t, (uint32_t)p->n, err);
    if (st != PG_OK) return st;
    if (!(*out = pg_inspect_height_field(p)))
        return pg_error_set(err, PG_ERR_NOMEM, "inspect: out of memory for the heights");
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.method = PG_PITS_FILL;
    o.epsilon = true;
    o.has_sea_level = true;
    o.sea_level = p->sea_level;
    st = pg_pits_remove(&t, *out, &o, NULL, err);
    if (st != PG_OK) free(*out), *out = NULL;
    return st;
}

/* Drainage of p's pit-free heights, and the depressions of its heights as given. */
static pg_status measure_water(const pg_planet *p, stage_clock *c, float **acc_out, pg_error *err) {
    pg_realism *out = c->out;
    begin(c, PG_REALISM_DEPRESSIONS);
    pg_status st = pg_inspect_depressions(p, &out->depressions, err);
    end(c);
    if (st != PG_OK) return st;
    begin(c, PG_REALISM_DRAINAGE);
    float *h = NULL;
    st = filled_heights(p, &h, err);
    if (st == PG_OK) {
        /* the filled heights, everything else the planet's */
        pg_drainage_terrain q = pg_planet_drainage_terrain(p);
        size_t nn = (size_t)(p->n * p->n);
        for (int f = 0; f < PG_CUBE_NFACES; f++)
            q.height[f] = h + (size_t)f * nn;
        st = pg_drainage_planet(&q, NULL, &out->drainage, acc_out, err);
    }
    free(h);
    end(c);
    return st;
}

/* The closed land share before the final pass: generate records it; heights that
 * still have depressions are themselves before any final pass. */
static pg_status closed_share(const pg_planet *p, pg_realism *out, pg_error *err) {
    out->closed_land_share_before_final = p->closed_land_share_before_final;
    if (isfinite(out->closed_land_share_before_final) || !out->depressions.depressions)
        return PG_OK;
    float *h = pg_inspect_height_field(p);
    if (!h) return pg_error_set(err, PG_ERR_NOMEM, "inspect: out of memory for the heights");
    pg_status st =
        pg_drainage_closed_land_share(h, p->n, p->projection, &p->ellipsoid, p->sea_level,
                                      &out->closed_land_share_before_final, err);
    free(h);
    return st;
}

pg_status pg_realism_planet(const pg_planet *p, const pg_exemplar *ex,
                            const pg_inspect_fid_exemplar *fx, const pg_realism *earth,
                            pg_realism_progress_fn progress, void *user, pg_realism *out,
                            float **acc_out, pg_inspect_distortion *dist_out, pg_error *err) {
    memset(out, 0, sizeof *out);
    if (acc_out) *acc_out = NULL;
    stage_clock c = {progress, user, out, 0, 0};
    pg_status st = measure_surface(p, ex, fx, &c, dist_out, err);
    if (st == PG_OK) st = measure_water(p, &c, acc_out, err);
    if (st == PG_OK) st = closed_share(p, out, err);
    if (st == PG_OK) compare(out, earth);
    if (st != PG_OK && acc_out) free(*acc_out), *acc_out = NULL;
    return st;
}

/* ---- Earth's side ---- */

pg_status pg_realism_earth(const pg_planet *geometry, const pg_exemplar *ex,
                           pg_realism_progress_fn progress, void *user, pg_realism *out,
                           pg_inspect_fid_exemplar **fx_out, pg_error *err) {
    memset(out, 0, sizeof *out);
    *fx_out = NULL;
    pg_planet e;
    pg_status st = pg_planet_alloc(&e, geometry->projection, geometry->tiles, geometry->tile_size,
                                   geometry->ellipsoid, err);
    if (st != PG_OK) return st;
    st = pg_planet_from_exemplar(&e, ex, 2, err);
    if (st == PG_OK) st = pg_planet_source_identity(&e, (int)e.n, e.projection, err);
    stage_clock c = {progress, user, out, 0, 0};
    if (st == PG_OK) {
        begin(&c, PG_REALISM_FIDELITY);
        st = pg_inspect_fid_exemplar_build(&e, ex, fx_out, err);
        end(&c);
    }
    if (st == PG_OK) st = measure_surface(&e, ex, *fx_out, &c, NULL, err);
    if (st == PG_OK) st = measure_water(&e, &c, NULL, err);
    if (st == PG_OK) st = closed_share(&e, out, err);
    if (st == PG_OK) compare(out, out);
    pg_planet_free(&e);
    if (st != PG_OK) pg_inspect_fid_exemplar_free(*fx_out), *fx_out = NULL;
    return st;
}

static uint64_t earth_key(const pg_planet *g, const pg_exemplar *ex) {
    /* the code that computed the figures: any change to the library's sources makes
     * older cache files foreign (PG_SOURCE_HASH, scripts/hash-sources.cmake) */
    const char *tag = "planetgen-realism-earth " PG_SOURCE_HASH;
    uint64_t k = pg_synth_hash_bytes(0xcbf29ce484222325ULL, tag, strlen(tag));
    int64_t ints[6] = {g->projection, g->tiles,   g->tile_size,
                       ex->width,     ex->height, (int64_t)sizeof(pg_realism)};
    double dbl[3] = {g->ellipsoid.a, g->ellipsoid.f, ex->sea_level};
    k = pg_synth_hash_bytes(k, ints, sizeof ints);
    k = pg_synth_hash_bytes(k, dbl, sizeof dbl);
    size_t np = (size_t)ex->width * (size_t)ex->height;
    k = pg_synth_hash_bytes(k, ex->albedo, np * 3 * sizeof(float));
    return pg_synth_hash_bytes(k, ex->elevation, np * sizeof(float));
}

#define EARTH_MAGIC "PGREAL01"

static bool load_earth(const char *path, uint64_t key, pg_realism *out) {
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    char magic[8];
    uint64_t k = 0, size = 0;
    bool ok = fread(magic, 8, 1, f) == 1 && !memcmp(magic, EARTH_MAGIC, 8) &&
              fread(&k, sizeof k, 1, f) == 1 && k == key && fread(&size, sizeof size, 1, f) == 1 &&
              size == sizeof *out && fread(out, sizeof *out, 1, f) == 1;
    fclose(f);
    return ok;
}

/* Written under a temporary name and renamed, so readers never see half a file. A
 * cache that cannot be written is not an error: the figures are still right. */
/* mkdir -p: every missing folder of dir (errors surface when the file is written). */
static void make_dirs(const char *dir) {
    char buf[512];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *s = buf + 1; *s; s++)
        if (*s == '/') {
            *s = 0;
            mkdir(buf, 0755);
            *s = '/';
        }
    mkdir(buf, 0755);
}

static void save_earth(const char *dir, const char *path, uint64_t key, const pg_realism *r) {
    make_dirs(dir);
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) return;
    uint64_t size = sizeof *r;
    bool ok = fwrite(EARTH_MAGIC, 8, 1, f) == 1 && fwrite(&key, sizeof key, 1, f) == 1 &&
              fwrite(&size, sizeof size, 1, f) == 1 && fwrite(r, sizeof *r, 1, f) == 1;
    if (fclose(f) != 0) ok = false;
    if (!ok || rename(tmp, path) != 0) remove(tmp);
}

pg_status pg_realism_earth_cached(const pg_planet *geometry, const pg_exemplar *ex,
                                  const char *cache_dir, pg_realism_progress_fn progress,
                                  void *user, pg_realism *out, pg_inspect_fid_exemplar **fx_out,
                                  bool *from_cache, pg_error *err) {
    char dir[512], path[1024], fpath[1024];
    if (!cache_dir)
        pg_synth_default_cache_dir(dir, sizeof dir);
    else
        snprintf(dir, sizeof dir, "%s", cache_dir);
    uint64_t key = earth_key(geometry, ex);
    snprintf(path, sizeof path, "%s/realism-earth-%016llx.bin", dir, (unsigned long long)key);
    snprintf(fpath, sizeof fpath, "%s/realism-fidelity-%016llx.bin", dir, (unsigned long long)key);
    *fx_out = NULL;
    *from_cache = dir[0] && load_earth(path, key, out) &&
                  (*fx_out = pg_inspect_fid_exemplar_load(fpath, key)) != NULL;
    if (*from_cache) return PG_OK;
    pg_status st = pg_realism_earth(geometry, ex, progress, user, out, fx_out, err);
    if (st == PG_OK && dir[0]) {
        pg_error werr = {0}; /* a cache that cannot be written is not an error */
        save_earth(dir, path, key, out);
        pg_inspect_fid_exemplar_save(*fx_out, fpath, key, &werr);
    }
    return st;
}
