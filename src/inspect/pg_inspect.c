/* pg_inspect.c - the pole check and depression figures of pg_inspect.h.
 *
 * The idea of the pole check: render the same six views (pg_views.h) from the planet
 * and from the exemplar, and ask the LPIPS-style metric how far the planet is from the
 * exemplar at the poles compared with the equator. Pole distortion - pinching,
 * smearing, stretched texture - raises only the pole distances, so the ratio exposes
 * it whatever the planet's overall distance from its exemplar. The exemplar is
 * rendered twice: from the original equirectangular image (the reference) and from
 * its reprojection onto a cube of the planet's geometry, whose distance to the
 * reference is what resampling alone costs (the floor). */
#include "planetgen/pg_inspect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *pg_inspect_source_name(int src) {
    static const char *names[PG_INSPECT_NSRC] = {"planet", "exemplar_cube", "exemplar_equirect"};
    return (src >= 0 && src < PG_INSPECT_NSRC) ? names[src] : "?";
}

void pg_inspect_views_free(pg_inspect_views *v) {
    for (int s = 0; s < PG_INSPECT_NSRC; s++)
        for (int k = 0; k < PG_VIEWS_COUNT; k++)
            pg_view_free(&v->v[s][k]);
}

/* The planet's faces as one 6*n*n*4 buffer (R, G, B, height) for pg_cube_sample. */
static float *pack_planet(const pg_planet *p) {
    size_t nn = (size_t)p->n * p->n;
    float *b = malloc(6 * nn * 4 * sizeof *b);
    if (!b) return NULL;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (size_t i = 0; i < nn; i++) {
            float *d = b + ((size_t)f * nn + i) * 4;
            memcpy(d, p->albedo[f] + 3 * i, 3 * sizeof *d);
            d[3] = p->height[f][i];
        }
    return b;
}

pg_status pg_inspect_exemplar_cube(const pg_planet *p, int64_t n, const pg_exemplar *ex,
                                   float **out, pg_error *err) {
    size_t np = (size_t)ex->width * ex->height, nn = (size_t)n * n;
    float *rgbh = malloc(np * 4 * sizeof *rgbh);
    *out = malloc(6 * nn * 4 * sizeof **out);
    if (!rgbh || !*out) {
        free(rgbh), free(*out);
        *out = NULL;
        return pg_error_set(err, PG_ERR_NOMEM, "inspect: out of memory for the exemplar cube");
    }
    for (size_t i = 0; i < np; i++) {
        memcpy(rgbh + 4 * i, ex->albedo + 3 * i, 3 * sizeof *rgbh);
        rgbh[4 * i + 3] = ex->elevation[i];
    }
    pg_status st = pg_cube_from_equirect(p->projection, n, &p->ellipsoid, rgbh, ex->width,
                                         ex->height, 4, 2, *out, err);
    free(rgbh);
    if (st != PG_OK) {
        free(*out);
        *out = NULL;
    }
    return st;
}

static pg_status render_source(int src, pg_views_sampler s, void *user, pg_inspect_views *out,
                               pg_error *err) {
    for (int k = 0; k < PG_VIEWS_COUNT; k++) {
        pg_status st = pg_views_render(k, out->size, out->fov_deg, out->sigma_deg, s, user,
                                       &out->v[src][k], err);
        if (st != PG_OK) return st;
    }
    return PG_OK;
}

static pg_status render_views(const pg_planet *p, const pg_exemplar *ex, int size, bool floor,
                              pg_inspect_views *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    out->size = size;
    out->fov_deg = PG_VIEWS_DEFAULT_FOV_DEG;
    /* one prefilter for every source: the coarsest of view pixel, planet texel (at a face
     * centre) and exemplar pixel (at the equator) */
    out->sigma_deg =
        pg_views_prefilter_deg(size, out->fov_deg, 90.0 / (double)p->n, 360.0 / ex->width);
    float *planet = pack_planet(p), *excube = NULL;
    if (!planet) return pg_error_set(err, PG_ERR_NOMEM, "inspect: out of memory for the planet");
    pg_views_cube_src ps = {p->projection, p->n, planet};
    pg_status st = render_source(PG_INSPECT_SRC_PLANET, pg_views_sample_cube, &ps, out, err);
    free(planet);
    if (st == PG_OK && floor) st = pg_inspect_exemplar_cube(p, p->n, ex, &excube, err);
    if (st == PG_OK && floor) {
        pg_views_cube_src cs = {p->projection, p->n, excube};
        st = render_source(PG_INSPECT_SRC_EXCUBE, pg_views_sample_cube, &cs, out, err);
    }
    free(excube);
    if (st == PG_OK) {
        pg_views_equirect_src es = {ex->albedo, ex->elevation, ex->width, ex->height, p->ellipsoid};
        st = render_source(PG_INSPECT_SRC_EXRECT, pg_views_sample_equirect, &es, out, err);
    }
    if (st != PG_OK) pg_inspect_views_free(out);
    return st;
}

pg_status pg_inspect_render_views(const pg_planet *p, const pg_exemplar *ex, int size,
                                  pg_inspect_views *out, pg_error *err) {
    return render_views(p, ex, size, true, out, err);
}

pg_status pg_inspect_render_views_nofloor(const pg_planet *p, const pg_exemplar *ex, int size,
                                          pg_inspect_views *out, pg_error *err) {
    return render_views(p, ex, size, false, out, err);
}

static pg_status view_features(const pg_view *v, const pg_lpips_params *lp, pg_lpips_features *f,
                               pg_error *err) {
    pg_lpips_image img = {v->size, v->size, v->rgb, v->height};
    return pg_lpips_features_compute(&img, lp, f, err);
}

/* Distances of one view: every source against the exemplar equirect, and the planet
 * against the exemplar cube. */
static pg_status score_view(const pg_inspect_views *v, int k, const pg_lpips_params *lp,
                            pg_inspect_poles *out, pg_error *err) {
    pg_lpips_features f[PG_INSPECT_NSRC];
    memset(f, 0, sizeof f);
    pg_status st = PG_OK;
    bool floor = v->v[PG_INSPECT_SRC_EXCUBE][k].size > 0; /* not rendered: NaN */
    out->d[PG_INSPECT_SRC_EXCUBE][k].distance = out->d_vs_cube[k].distance = NAN;
    for (int s = 0; s < PG_INSPECT_NSRC && st == PG_OK; s++)
        if (s != PG_INSPECT_SRC_EXCUBE || floor) st = view_features(&v->v[s][k], lp, &f[s], err);
    for (int s = 0; s < PG_INSPECT_NSRC && st == PG_OK; s++)
        if (s != PG_INSPECT_SRC_EXCUBE || floor)
            st = pg_lpips_compare(&f[s], &f[PG_INSPECT_SRC_EXRECT], &out->d[s][k], err);
    if (st == PG_OK && floor)
        st = pg_lpips_compare(&f[PG_INSPECT_SRC_PLANET], &f[PG_INSPECT_SRC_EXCUBE],
                              &out->d_vs_cube[k], err);
    for (int s = 0; s < PG_INSPECT_NSRC; s++)
        pg_lpips_features_free(&f[s]);
    return st;
}

/* Ratio of each pole's distance to the mean equator distance, for one source, with
 * `jnd` added to both sides. */
static void ratios(const pg_lpips_result d[PG_VIEWS_COUNT], double jnd, double *eq, double *rn,
                   double *rs) {
    *eq = 0;
    for (int k = PG_VIEW_EQ_0; k <= PG_VIEW_EQ_90W; k++)
        *eq += d[k].distance / 4;
    *rn = *eq + jnd > 0 ? (d[PG_VIEW_NORTH].distance + jnd) / (*eq + jnd) : NAN;
    *rs = *eq + jnd > 0 ? (d[PG_VIEW_SOUTH].distance + jnd) / (*eq + jnd) : NAN;
}

pg_status pg_inspect_pole_scores(const pg_inspect_views *v, const pg_lpips_params *lp,
                                 pg_inspect_poles *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    for (int k = 0; k < PG_VIEWS_COUNT; k++) {
        pg_status st = score_view(v, k, lp, out, err);
        if (st != PG_OK) return st;
    }
    ratios(out->d[PG_INSPECT_SRC_PLANET], PG_INSPECT_JND, &out->equator_mean, &out->ratio_north,
           &out->ratio_south);
    out->pole_equator_ratio = fmax(out->ratio_north, out->ratio_south);
    double eq, rn, rs;
    ratios(out->d[PG_INSPECT_SRC_PLANET], 0, &eq, &out->raw_north, &out->raw_south);
    ratios(out->d[PG_INSPECT_SRC_EXCUBE], PG_INSPECT_JND, &eq, &rn, &rs);
    out->floor_ratio = fmax(rn, rs);
    return PG_OK;
}

float *pg_inspect_height_field(const pg_planet *p) {
    size_t nn = (size_t)p->n * p->n;
    float *h = malloc(6 * nn * sizeof *h);
    if (h)
        for (int f = 0; f < PG_CUBE_NFACES; f++)
            memcpy(h + f * nn, p->height[f], nn * sizeof *h);
    return h;
}

pg_status pg_inspect_depressions(const pg_planet *p, pg_pits_stats *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_pits_topo t;
    pg_status st = pg_pits_topo_cube(&t, (uint32_t)p->n, err);
    if (st != PG_OK) return st;
    float *h = pg_inspect_height_field(p);
    if (!h) return pg_error_set(err, PG_ERR_NOMEM, "inspect: out of memory for the heights");
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = true;
    o.sea_level = p->sea_level;
    pg_pits_area area;
    memset(&area, 0, sizeof area);
    /* the mean texel area (texel areas vary across a face: see the distortion table) */
    area.constant = pg_geo_total_area(&p->ellipsoid) / (6.0 * (double)p->n * (double)p->n);
    st = pg_pits_stats_compute(&t, h, &o, &area, out, err);
    free(h);
    return st;
}
