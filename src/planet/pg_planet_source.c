/* pg_planet_source.c - the planet's coordinate map: which exemplar-cube texel each
 * planet texel was copied from (pg_planet.h, pg_planet_source).
 *
 * Synthesis works on packed exemplar coordinates (pg_synth.h): face, u, v of the
 * exemplar cube plus an orientation. The map keeps face, u and v only; orientation
 * says how a patch was turned, which the measures read from the geometry of
 * neighbouring sources instead. Directions come from the exemplar cube's own
 * projection, so a planet and its exemplar may have different face sizes and
 * projections. */
#include "planetgen/pg_planet.h"
#include "planetgen/pg_synth.h"

#include <stdlib.h>

pg_status pg_planet_source_alloc(pg_planet *p, int face_size, pg_cube_projection proj,
                                 pg_error *err) {
    pg_planet_source_free(p);
    if (face_size < 1 || face_size > PG_SYNTH_MAX_FACE_SIZE)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "coordinate map: exemplar face size %d outside 1..%d", face_size,
                            PG_SYNTH_MAX_FACE_SIZE);
    size_t nn = (size_t)p->n * (size_t)p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        if (!(p->source.coords[f] = calloc(nn, sizeof(uint32_t)))) {
            pg_planet_source_free(p);
            return pg_error_set(err, PG_ERR_NOMEM, "coordinate map: out of memory");
        }
    p->source.face_size = face_size;
    p->source.projection = proj;
    return PG_OK;
}

void pg_planet_source_free(pg_planet *p) {
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        free(p->source.coords[f]);
        p->source.coords[f] = NULL;
    }
    p->source.face_size = 0;
}

bool pg_planet_has_source(const pg_planet *p) {
    return p->source.face_size > 0 && p->source.coords[0] != NULL;
}

void pg_planet_source_dir(const pg_planet *p, int face, int64_t x, int64_t y, double dir[3]) {
    uint32_t c = p->source.coords[face][(size_t)y * (size_t)p->n + (size_t)x];
    double e = p->source.face_size;
    pg_cube_to_dir(p->source.projection, pg_synth_face(c), (2.0 * pg_synth_u(c) + 1.0) / e - 1.0,
                   (2.0 * pg_synth_v(c) + 1.0) / e - 1.0, dir);
}

/* Nearest texel index of grid coordinate t in [-1, 1] on a face of e texels. */
static int nearest_texel(double t, int e) {
    int i = (int)((t + 1.0) * 0.5 * e);
    return i < 0 ? 0 : (i >= e ? e - 1 : i);
}

pg_status pg_planet_source_identity(pg_planet *p, int face_size, pg_cube_projection proj,
                                    pg_error *err) {
    pg_status st = pg_planet_source_alloc(p, face_size, proj, err);
    if (st != PG_OK) return st;
    const int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        uint32_t *c = p->source.coords[f];
#pragma omp parallel for schedule(static)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                double d[3], u, v;
                int ef;
                pg_cube_to_dir(p->projection, f, (2.0 * x + 1.0) / n - 1.0,
                               (2.0 * y + 1.0) / n - 1.0, d);
                pg_cube_from_dir(proj, d, &ef, &u, &v);
                c[y * n + x] =
                    pg_synth_pack(ef, nearest_texel(u, face_size), nearest_texel(v, face_size));
            }
    }
    return PG_OK;
}
