/* pg_planet_synth_params.c - the planet synthesis's parameters: defaults, the sizes the
 * driver derives from the exemplar (synthesized face size, magnification, kept levels,
 * the exemplar cube's face size), the memory estimate and the checks made before any
 * allocation (docs/generate.md, "Method": "Pyramid", "Exemplar scale", "Layout earth"). */
#include "pg_planet_synth_internal.h"

#include <string.h>

void pg_planet_synth_params_default(pg_planet_synth_params *p) {
    memset(p, 0, sizeof *p);
    p->tiles = 4;
    p->tile_size = 256;
    pg_synth_params_default(&p->synth);
    p->synth.grid_shape = PG_PLANET_GRID_SHAPE;
    p->layout = PG_LAYOUT_EARTH;
    p->keep_levels = PG_PLANET_KEEP_AUTO;
    p->guide_alpha = 0.8;
    p->type_mask = PG_TYPES_ALL;
    p->pits = true;
    p->pit_skip_levels = 1;
    p->pit_method = PG_PITS_BREACH;
    p->final_pits = true;
    p->sea_ice = true;
    p->final_method = PG_PITS_BREACH;
    p->pit_stats = true;
}

/* The synthesis copies exemplar texels one to one, so a planet whose faces have more
 * texels than the exemplar cube's (the default: 1024 against 512) would show every
 * exemplar feature at 1/m of its size, and with layout earth (coarsest texels at the
 * same direction, m times closer in the exemplar than the synthesis spaces them) lay
 * each feature down m times per axis: the Arctic archipelago became a lattice of
 * repeated islands, Novaya Zemlya two parallel copies. So synthesize at N / m, the
 * largest power-of-two reduction that keeps at least the exemplar's face size and a
 * whole pyramid per tile, and magnify at delivery. */
int pg_planet_synth_magnification(const pg_synth_exemplar *ex, const pg_planet_synth_params *p) {
    const int64_t n = (int64_t)p->tiles * p->tile_size;
    const int need = 1 << pg_ps_top_scale(ex);
    int m = 1;
    while (n / (2 * m) >= ex->face_size && p->tile_size % (2 * m) == 0 &&
           (p->tile_size / (2 * m)) % need == 0)
        m *= 2;
    return m;
}

/* Layout earth keeps, unjittered, the levels whose texel spacing is at least 1/32 of a
 * face (about 280 km on the Earth), whatever the exemplar's resolution: spacing 2^s
 * exemplar texels of a face of E, so s >= log2(E) - 5. Counting the levels by number
 * instead would keep twice as fine a structure at E = 1024 as at 512 and make a larger
 * exemplar a closer copy of the Earth, not a finer planet. At least the coarsest level
 * is kept, or the layout would not be the Earth's. */
int pg_planet_synth_keep_levels(const pg_synth_exemplar *ex, const pg_planet_synth_params *p) {
    if (p->keep_levels != PG_PLANET_KEEP_AUTO) return p->keep_levels;
    int log2e = 0;
    while ((1 << (log2e + 1)) <= ex->face_size)
        log2e++;
    int keep = pg_ps_top_scale(ex) - (log2e - 5) + 1;
    return keep < 1 ? 1 : (keep > ex->levels ? ex->levels : keep);
}

/* The exemplar cube as fine as the planet (so nothing is magnified), within
 * [PG_PLANET_FACE_MIN, PG_PLANET_FACE_AUTO_MAX]: below 512 the 6 analysed levels do not
 * fit, and above the cap the exemplar outgrows a workstation (about 200 B per exemplar
 * texel while it is prepared: 5 GB at 2048, 20 GB at 4096) and the default source data
 * holds no finer detail (Blue Marble has 675 px per face, Marble's relief 2700). */
int pg_planet_synth_face_size(int tiles, int tile_size) {
    int64_t n = (int64_t)tiles * tile_size;
    int e = PG_PLANET_FACE_MIN;
    while (e < n && e < PG_PLANET_FACE_AUTO_MAX)
        e *= 2;
    return e;
}

/* Bytes per finest texel, by phase (see pg_planet_synth_run for the order of
 * allocations): synthesis (S, V with borders, the parent level, orient, type mask,
 * the world's temperature, guide, Gain-pit at the next-finest level) and delivery (planet 16, S and
 * H 8, and what the final pit removal allocates, about 10); the sea ice's noise grids on top. */
double pg_planet_synth_bytes(int tiles, int tile_size, const pg_planet_synth_params *p) {
    double n = (double)tiles * tile_size, px = 6.0 * n * n;
    double border = 6.0 * 4.0 * (n + 2) * 2 * 16;
    double synth = 8 * 1.25 + 1 + (p && (p->types || pg_ps_world_types(p)) ? 1 : 0) +
                   (p && pg_ps_world_climate(p) ? 1 : 0) + /* the world's temperature */
                   (p && (p->guide || pg_ps_world_guide(p)) ? 4 : 0) +
                   (p && p->pits ? 0.25 * 18 : 0);
    double deliver = 16 + 8 + (p && p->pits ? 12 : 0);
    /* checked before the world exists: then its size as generate builds it */
    double ice = p && p->sea_ice && p->layout == PG_LAYOUT_WORLD
                     ? pg_sea_ice_bytes((int64_t)n, p->world ? p->world->n : PG_SEA_ICE_WORLD_N)
                     : 0;
    return px * (synth > deliver ? synth : deliver) + border + ice;
}

pg_status pg_planet_synth_check(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                                pg_error *err) {
    if (!ex) return pg_error_set(err, PG_ERR_BADINPUT, "planet synthesis: no exemplar");
    /* the planet's faces draw and read exemplar faces 0..5 */
    if (ex->nfaces != 6)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "planet synthesis: the exemplar must be a cube of 6 faces, not a "
                            "toroidal tile of %d",
                            ex->nfaces);
    if (p->tiles < 1 || p->tiles > 4096)
        return pg_error_set(err, PG_ERR_BADINPUT, "--tiles %d: must be in 1..4096", p->tiles);
    int S = p->tile_size, need = 1 << pg_ps_top_scale(ex);
    if (S < 16 || S > 8192 || (S & (S - 1)))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--tile-size %d: must be a power of two in 16..8192", S);
    if (S % need)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--tile-size %d: does not divide into the %d-level pyramid (must be "
                            "a multiple of 2^%d = %d so the coarsest level has whole texels per "
                            "tile)",
                            S, ex->levels, pg_ps_top_scale(ex), need);
    if ((int64_t)p->tiles * S > 65536)
        return pg_error_set(err, PG_ERR_BADINPUT, "--tiles x --tile-size %lld: too large",
                            (long long)p->tiles * S);
    if (p->keep_levels < PG_PLANET_KEEP_AUTO || p->keep_levels > ex->levels)
        return pg_error_set(err, PG_ERR_BADINPUT, "--keep-levels %d: must be in 0..%d",
                            p->keep_levels, ex->levels);
    if (p->pit_skip_levels < 0 || p->pit_skip_levels > ex->levels)
        return pg_error_set(err, PG_ERR_BADINPUT, "--pit-skip-levels %d: must be in 0..%d",
                            p->pit_skip_levels, ex->levels);
    if (!(p->guide_alpha >= 0 && p->guide_alpha <= 1))
        return pg_error_set(err, PG_ERR_BADINPUT, "--guide-weight %g: must be in [0, 1]",
                            p->guide_alpha);
    if (p->layout == PG_LAYOUT_WORLD &&
        (!p->world || !p->world->elevation_m || !p->world->temperature_c ||
         !p->world->precipitation_mm || p->world->n < 1))
        return pg_error_set(err, PG_ERR_BADINPUT, "--layout world: no macro world");
    if (!(p->type_mask & PG_TYPES_ALL))
        return pg_error_set(err, PG_ERR_BADINPUT, "types: no type allowed");
    return PG_OK;
}

/* The one place that says how the synthesis removes pits (declared in pg_planet_synth.h). */
void pg_planet_synth_pits_opts(pg_pits_method m, float sea_level, pg_pits_opts *o) {
    pg_pits_opts_default(o);
    o->method = m;
    o->epsilon = true;
    o->descent = true; /* no flood order: MPI ranks reproduce it (docs/mpi.md) */
    o->has_sea_level = true;
    o->sea_level = sea_level;
}
