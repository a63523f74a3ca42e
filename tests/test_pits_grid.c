/* test_pits_grid.c - pit removal on flat 8-connected grids: every method leaves no
 * pits (independent checker), plain fill equals the brute-force minimal fill and fill
 * with epsilon the brute-force minimal epsilon-surface (bit for bit), fill
 * never lowers and breach never raises, hybrid honours its limits, results do not
 * depend on the thread count, depressions are counted, bad input is refused. */
#include "pg_test.h"
#include "pits_checker.h"
#include "planetgen/pg_pits.h"
#include "pg_pits_internal.h"

#include <omp.h>
#include <stdio.h>

/* Deterministic test randomness: a hash of (seed, index). */
static uint32_t hash32(uint32_t a, uint32_t b) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    h *= 0x297A2D39u;
    return h ^ (h >> 15);
}

/* Random terrain: noisy, pitted, sometimes quantised (flats), with a sea. */
static float *random_dem(uint32_t seed, int w, int h) {
    float *d = malloc(sizeof(float) * (size_t)w * h);
    int quant = seed % 3 == 0;
    for (int i = 0; i < w * h; i++) {
        int x = i % w, y = i / w;
        double v =
            30.0 * sin(0.3 * x + seed) * cos(0.25 * y) + 20.0 * (hash32(seed, i) / 4294967296.0);
        d[i] = quant ? (float)floor(v / 4) * 4 : (float)v;
    }
    return d;
}

typedef struct variant {
    pg_pits_method m;
    bool eps, descent;
} variant;

static const variant VARIANTS[] = {{PG_PITS_FILL, false, false},   {PG_PITS_FILL, true, false},
                                   {PG_PITS_BREACH, false, false}, {PG_PITS_BREACH, true, false},
                                   {PG_PITS_HYBRID, false, false}, {PG_PITS_HYBRID, true, false},
                                   {PG_PITS_BREACH, false, true},  {PG_PITS_BREACH, true, true},
                                   {PG_PITS_HYBRID, false, true},  {PG_PITS_HYBRID, true, true}};

static void set_sinks(pg_pits_opts *o, uint32_t seed) {
    o->has_sea_level = seed % 4 != 1;
    o->sea_level = -10.0;
    o->open_edges = seed % 2 == 0;
}

/* All methods, many random grids: pit-free by the independent checker. */
static void test_all_methods_drain(void **state) {
    (void)state;
    for (uint32_t seed = 0; seed < 60; seed++) {
        int w = 1 + (int)(hash32(seed, 1) % 40), h = 1 + (int)(hash32(seed, 2) % 40);
        float *dem = random_dem(seed, w, h);
        chk_graph g = chk_grid_graph(w, h);
        pg_pits_topo t;
        assert_int_equal(pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL), PG_OK);
        for (size_t v = 0; v < sizeof VARIANTS / sizeof *VARIANTS; v++) {
            pg_pits_opts o;
            pg_pits_opts_default(&o);
            o.method = VARIANTS[v].m;
            o.epsilon = VARIANTS[v].eps;
            o.descent = VARIANTS[v].descent;
            o.max_depth = 6;
            o.max_length = 5;
            set_sinks(&o, seed);
            float *out = malloc(sizeof(float) * (size_t)w * h);
            memcpy(out, dem, sizeof(float) * (size_t)w * h);
            pg_error err = {0};
            assert_int_equal(pg_pits_remove(&t, out, &o, NULL, &err), PG_OK);
            uint8_t *sk =
                chk_sinks(dem, g.n, o.has_sea_level, o.sea_level, NULL, o.open_edges, w, h);
            /* before: random terrain has pits (when it is not tiny) */
            if (seed == 5) assert_true(chk_undrained(&g, dem, sk, 0) > 0);
            size_t bad = chk_undrained(&g, out, sk, o.epsilon);
            if (bad)
                fprintf(stderr, "seed %u %dx%d %s eps %d: %zu undrained\n", seed, w, h,
                        pg_pits_method_name(o.method), o.epsilon, bad);
            assert_int_equal(bad, 0);
            /* direction */
            for (size_t i = 0; i < g.n; i++) {
                if (o.method == PG_PITS_FILL) assert_true(out[i] >= dem[i]);
                if (o.method == PG_PITS_BREACH) assert_true(out[i] <= dem[i]);
                if (o.method == PG_PITS_HYBRID) assert_true(dem[i] - out[i] <= o.max_depth);
                if (sk[i]) assert_true(out[i] == dem[i]);
            }
            free(sk);
            free(out);
        }
        chk_graph_free(&g);
        free(dem);
    }
}

/* Plain fill, serial and tiled-parallel (Barnes 2016), equals the brute-force minimal
 * fill bit for bit. */
static void test_exact_fill(void **state) {
    (void)state;
    size_t raised_by_eps = 0;
    for (uint32_t seed = 100; seed < 160; seed++) {
        int w = 1 + (int)(hash32(seed, 1) % 30), h = 1 + (int)(hash32(seed, 2) % 30);
        float *dem = random_dem(seed, w, h);
        chk_graph g = chk_grid_graph(w, h);
        pg_pits_topo t;
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        o.method = PG_PITS_FILL;
        o.epsilon = false;
        set_sinks(&o, seed);
        uint8_t *lakes = NULL;
        if (seed % 5 == 0) { /* a lakes mask too */
            lakes = calloc(g.n, 1);
            lakes[hash32(seed, 9) % g.n] = 1;
        }
        o.lakes = lakes;
        float *out = malloc(sizeof(float) * g.n);
        uint8_t *sk = chk_sinks(dem, g.n, o.has_sea_level, o.sea_level, lakes, o.open_edges, w, h);
        float *ref = chk_minimal_fill(&g, dem, sk);
        /* serial (tiny grids), then the tiled parallel fill with 1-, 2- and 5-row tiles */
        int tiles[] = {0, 1, 2, 5};
        for (int k = 0; k < 4; k++) {
            memcpy(out, dem, sizeof(float) * g.n);
            o.tile_rows = tiles[k];
            assert_int_equal(pg_pits_remove(&t, out, &o, NULL, NULL), PG_OK);
            for (size_t i = 0; i < g.n; i++)
                assert_true(out[i] == ref[i]);
        }
        /* with epsilon: bit for bit Planchon & Darboux's minimal epsilon-surface, which
         * lies between the minimal fill and every other epsilon-surface */
        float *eref = chk_minimal_fill_eps(&g, dem, sk, 1);
        memcpy(out, dem, sizeof(float) * g.n);
        o.epsilon = true;
        assert_int_equal(pg_pits_remove(&t, out, &o, NULL, NULL), PG_OK);
        size_t differ = 0, above = 0;
        for (size_t i = 0; i < g.n; i++) {
            differ += memcmp(&out[i], &eref[i], sizeof(float)) != 0;
            above += eref[i] > ref[i];
        }
        if (differ)
            fail_msg("seed %u: %zu cells differ from the minimal epsilon-surface", seed, differ);
        raised_by_eps += above;
        free(eref);
        free(ref);
        free(sk);
        free(out);
        free(lakes);
        chk_graph_free(&g);
        free(dem);
    }
    assert_true(raised_by_eps > 0); /* the grids had flats for the ulps to slope */
}

/* Hybrid with max_length 0 can carve nothing: it is exactly the fill. With a depth
 * limit, no cell ends deeper than the limit below its start. Both trees. */
static void test_hybrid_limits(void **state) {
    (void)state;
    for (uint32_t seed = 200; seed < 230; seed++) {
        int w = 32, h = 24;
        float *dem = random_dem(seed, w, h);
        pg_pits_topo t;
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        for (int eps = 0; eps < 4; eps++) {
            pg_pits_opts o;
            pg_pits_opts_default(&o);
            set_sinks(&o, seed);
            o.descent = eps >= 2;
            o.epsilon = eps % 2;
            float *a = malloc(sizeof(float) * w * h), *b = malloc(sizeof(float) * w * h);
            memcpy(a, dem, sizeof(float) * w * h);
            memcpy(b, dem, sizeof(float) * w * h);
            o.method = PG_PITS_FILL;
            pg_pits_remove(&t, a, &o, NULL, NULL);
            o.method = PG_PITS_HYBRID;
            o.max_length = 0;
            pg_pits_result r;
            pg_pits_remove(&t, b, &o, &r, NULL);
            assert_memory_equal(a, b, sizeof(float) * w * h);
            assert_int_equal(r.lowered, 0);
            /* depth-limited, unlimited length */
            memcpy(b, dem, sizeof(float) * w * h);
            o.max_length = INFINITY;
            o.max_depth = 3.0;
            pg_pits_remove(&t, b, &o, &r, NULL);
            assert_true(r.max_lower <= 3.0);
            /* unlimited: breaches something on pitted terrain */
            memcpy(b, dem, sizeof(float) * w * h);
            o.max_depth = INFINITY;
            pg_pits_remove(&t, b, &o, &r, NULL);
            if (seed == 201) assert_true(r.breaches > 0);
            free(a);
            free(b);
        }
        free(dem);
    }
}

/* A pit whose breach channel is exactly 5 cells long: a corridor of 10 m between the
 * sea (x = 0) and the pit (x = 6), walls of 20 m. max_length 4 must fill it, 5 may
 * carve it; max_depth 8.9 (the channel needs 9 m: 10 m down to the pit at 1 m)
 * must fill it too. */
static void test_hybrid_length_limit(void **state) {
    (void)state;
    for (int descent = 0; descent < 2; descent++) {
        float dem[27];
        for (int i = 0; i < 27; i++)
            dem[i] = 20.0f;
        dem[9] = -1.0f; /* sea */
        for (int x = 1; x <= 5; x++)
            dem[9 + x] = 10.0f;
        dem[9 + 6] = 1.0f; /* the pit (above the sea level 0) */
        pg_pits_topo t;
        pg_pits_topo_grid(&t, 9, 3, NULL);
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        o.method = PG_PITS_HYBRID;
        o.epsilon = false; /* so the walls' flats stay exactly as they are */
        o.descent = descent;
        o.has_sea_level = true;
        o.sea_level = 0;
        double lengths[3] = {4, 5, 5}, depths[3] = {INFINITY, INFINITY, 8.9};
        for (int k = 0; k < 3; k++) {
            float h[27];
            memcpy(h, dem, sizeof h);
            o.max_length = lengths[k];
            o.max_depth = depths[k];
            pg_pits_result r;
            assert_int_equal(pg_pits_remove(&t, h, &o, &r, NULL), PG_OK);
            if (k == 1) { /* carved: the 5 corridor cells go below the pit, nothing rises */
                assert_int_equal(r.lowered, 5);
                assert_int_equal(r.raised, 0);
                for (int x = 1; x <= 5; x++)
                    assert_true(h[9 + x] < 1.0f);
            } else { /* filled: the pit rises to the corridor, nothing is carved */
                assert_int_equal(r.lowered, 0);
                assert_true(h[15] >= 10.0f);
            }
        }
    }
}

/* Results do not depend on the thread count. */
static void test_thread_invariance(void **state) {
    (void)state;
    int w = 300, h = 200;
    float *dem = random_dem(7, w, h);
    pg_pits_topo t;
    pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
    for (size_t v = 0; v < sizeof VARIANTS / sizeof *VARIANTS; v++) {
        float *a = malloc(sizeof(float) * w * h), *b = malloc(sizeof(float) * w * h);
        memcpy(a, dem, sizeof(float) * w * h);
        memcpy(b, dem, sizeof(float) * w * h);
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        o.method = VARIANTS[v].m;
        o.epsilon = VARIANTS[v].eps;
        o.max_depth = 5;
        o.max_length = 20;
        o.has_sea_level = true;
        o.sea_level = -5;
        omp_set_num_threads(1);
        pg_pits_remove(&t, a, &o, NULL, NULL);
        omp_set_num_threads(2);
        pg_pits_remove(&t, b, &o, NULL, NULL);
        assert_memory_equal(a, b, sizeof(float) * w * h);
        free(a);
        free(b);
    }
    free(dem);
}

/* A DEM of whole numbers with wide flats, the border its outlet, as a raw integer DEM:
 * most cells have no strictly descending path to a sink, so on 3 threads the epsilon
 * surface comes from the tiled fill and the flats' search instead of the flood
 * (docs/pits.md, "Hard DEM"). The epsilon fill is still the brute-force minimal
 * epsilon-surface bit for bit, and the descent-tree breach and hybrid built on it give
 * the same bytes on 1 and 3 threads. */
static void test_eps_by_fill(void **state) {
    (void)state;
    const variant cases[] = {
        {PG_PITS_FILL, true, false}, {PG_PITS_BREACH, true, true}, {PG_PITS_HYBRID, true, true}};
    for (uint32_t seed = 700; seed < 706; seed++) {
        int w = 90 + (int)(hash32(seed, 1) % 60), h = 60 + (int)(hash32(seed, 2) % 40);
        size_t n = (size_t)w * h;
        float *dem = malloc(sizeof(float) * n);
        for (size_t i = 0; i < n; i++) {
            int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
            double v = 40.0 * sin(0.05 * x + seed) * cos(0.07 * y) +
                       10.0 * (hash32(seed, (uint32_t)i) / 4294967296.0);
            dem[i] = (float)floor(v / 8);
        }
        chk_graph g = chk_grid_graph(w, h);
        uint8_t *sk = chk_sinks(dem, n, 0, 0, NULL, 1, w, h);
        /* the case the parallel path is for: most of the grid is left to the flood */
        assert_true(2 * chk_undrained(&g, dem, sk, 1) > n);
        float *eref = chk_minimal_fill_eps(&g, dem, sk, 1);
        pg_pits_topo t;
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        float *a = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
        for (size_t v = 0; v < sizeof cases / sizeof *cases; v++) {
            pg_pits_opts o;
            pg_pits_opts_default(&o);
            o.method = cases[v].m;
            o.epsilon = true;
            o.descent = cases[v].descent;
            o.open_edges = true;
            o.max_depth = 2;
            o.max_length = 15;
            memcpy(a, dem, sizeof(float) * n);
            memcpy(b, dem, sizeof(float) * n);
            omp_set_num_threads(1);
            assert_int_equal(pg_pits_remove(&t, a, &o, NULL, NULL), PG_OK);
            omp_set_num_threads(3); /* the fill's path is taken from three threads on */
            assert_int_equal(pg_pits_remove(&t, b, &o, NULL, NULL), PG_OK);
            omp_set_num_threads(2);
            assert_memory_equal(a, b, sizeof(float) * n);
            if (o.method == PG_PITS_FILL) assert_memory_equal(b, eref, sizeof(float) * n);
            assert_int_equal(chk_undrained(&g, b, sk, 1), 0);
        }
        free(a);
        free(b);
        free(eref);
        free(sk);
        chk_graph_free(&g);
        free(dem);
    }
}

/* Two separate square pits: 2 depressions of known area and volume; 0 after. */
static void test_stats(void **state) {
    (void)state;
    int w = 20, h = 10;
    float dem[200];
    for (int i = 0; i < 200; i++)
        dem[i] = 10.0f + (float)(i % w) * 0.1f; /* slope to x=0 */
    for (int y = 3; y < 6; y++)
        for (int x = 4; x < 7; x++)
            dem[y * w + x] = 0.0f; /* 3x3 pit, rim >= 10.3 */
    dem[5 * w + 15] = 1.0f;        /* single-cell pit */
    pg_pits_topo t;
    pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.open_edges = true;
    pg_pits_area area = {NULL, NULL, NULL, 4.0}; /* 2 m cells */
    pg_pits_stats st;
    assert_int_equal(pg_pits_stats_compute(&t, dem, &o, &area, &st, NULL), PG_OK);
    assert_int_equal(st.depressions, 2);
    assert_int_equal(st.depression_cells, 10);
    assert_true(fabs(st.depression_area_m2 - 40.0) < 1e-9);
    /* the 3x3 pit fills to its spill (the rim cell at x=3: 10.3) */
    double vol = 9 * 4.0 * 10.3 + 4.0 * (11.4 - 1.0);
    assert_true(fabs(st.depression_volume_m3 - vol) < 1e-3);
    for (int m = 0; m < 3; m++) {
        float out[200];
        memcpy(out, dem, sizeof out);
        o.method = (pg_pits_method)m;
        assert_int_equal(pg_pits_remove(&t, out, &o, NULL, NULL), PG_OK);
        assert_int_equal(pg_pits_stats_compute(&t, out, &o, &area, &st, NULL), PG_OK);
        assert_int_equal(st.depressions, 0);
        assert_true(st.depression_volume_m3 == 0.0);
    }
}

/* The statistics against an independent reference: depressions are the 8-connected
 * regions the brute-force minimal fill raises, their volume sum (minimal fill - h). On random grids
 * (pitted, flats, sinks of every kind) and on the result of every method (where the count mostly
 * takes its linear no-depression path, which must give exactly 0 everywhere and the same sink
 * count). */
static void check_stats_reference(const chk_graph *g, const pg_pits_topo *t, const float *dem,
                                  const pg_pits_opts *o, int w, int h) {
    uint8_t *sk = chk_sinks(dem, g->n, o->has_sea_level, o->sea_level, NULL, o->open_edges, w, h);
    float *ref = chk_minimal_fill(g, dem, sk);
    uint8_t *seen = calloc(g->n, 1);
    uint32_t *q = malloc(sizeof(uint32_t) * g->n);
    uint64_t regions = 0, cells = 0, nsinks = 0;
    double volume = 0;
    for (size_t i = 0; i < g->n; i++) {
        nsinks += sk[i];
        if (seen[i] || !(ref[i] > dem[i])) continue;
        regions++;
        size_t head = 0, tail = 0;
        q[tail++] = (uint32_t)i;
        seen[i] = 1;
        while (head < tail) {
            uint32_t c = q[head++];
            cells++;
            volume += (double)ref[c] - (double)dem[c];
            for (int j = 0; j < g->cnt[c]; j++) {
                uint32_t n = g->nb[8 * (size_t)c + j];
                if (!seen[n] && ref[n] > dem[n]) seen[n] = 1, q[tail++] = n;
            }
        }
    }
    pg_pits_stats st;
    assert_int_equal(pg_pits_stats_compute(t, dem, o, NULL, &st, NULL), PG_OK);
    assert_int_equal(st.depressions, regions);
    assert_int_equal(st.depression_cells, cells);
    assert_true(st.depression_area_m2 == (double)cells);
    assert_true(fabs(st.depression_volume_m3 - volume) <= 1e-9 * (1 + fabs(volume)));
    if (!nsinks) nsinks = 1; /* the lowest cell */
    assert_int_equal(st.sinks, nsinks);
    free(q);
    free(seen);
    free(ref);
    free(sk);
}

/* A random grid of 1..30 cells a side with its topology and the options the
 * statistics tests use (sinks from the seed, hybrid limits 6 and 5). */
static float *random_case(uint32_t seed, int *w, int *h, pg_pits_topo *t, pg_pits_opts *o) {
    *w = 1 + (int)(hash32(seed, 1) % 30);
    *h = 1 + (int)(hash32(seed, 2) % 30);
    pg_pits_topo_grid(t, (uint32_t)*w, (uint32_t)*h, NULL);
    pg_pits_opts_default(o);
    set_sinks(o, seed);
    o->max_depth = 6;
    o->max_length = 5;
    return random_dem(seed, *w, *h);
}

static void test_stats_reference(void **state) {
    (void)state;
    uint64_t with_depressions = 0, after_zero = 0;
    for (uint32_t seed = 200; seed < 240; seed++) {
        int w, h;
        pg_pits_topo t;
        pg_pits_opts o;
        float *dem = random_case(seed, &w, &h, &t, &o);
        chk_graph g = chk_grid_graph(w, h);
        check_stats_reference(&g, &t, dem, &o, w, h);
        pg_pits_stats st;
        pg_pits_stats_compute(&t, dem, &o, NULL, &st, NULL);
        with_depressions += st.depressions > 0;
        float *out = malloc(sizeof(float) * g.n);
        for (size_t v = 0; v < sizeof VARIANTS / sizeof *VARIANTS; v++) {
            memcpy(out, dem, sizeof(float) * g.n);
            o.method = VARIANTS[v].m;
            o.epsilon = VARIANTS[v].eps;
            o.descent = VARIANTS[v].descent;
            assert_int_equal(pg_pits_remove(&t, out, &o, NULL, NULL), PG_OK);
            check_stats_reference(&g, &t, out, &o, w, h);
            /* (without sea and edges, carving may move the lowest cell, the sink) */
            assert_int_equal(pg_pits_stats_compute(&t, out, &o, NULL, &st, NULL), PG_OK);
            if (!st.depressions) {
                assert_true(st.depression_volume_m3 == 0.0 && st.max_depth_m == 0.0);
                after_zero++;
            }
        }
        free(out);
        chk_graph_free(&g);
        free(dem);
    }
    assert_true(with_depressions > 20); /* the reference was not only zeros */
    assert_true(after_zero > 300);      /* and the no-depression path ran */
}

static void assert_same_stats(const pg_pits_stats *a, const pg_pits_stats *b) {
    assert_int_equal(a->depressions, b->depressions);
    assert_int_equal(a->depression_cells, b->depression_cells);
    assert_true(a->depression_area_m2 == b->depression_area_m2);
    assert_true(a->depression_volume_m3 == b->depression_volume_m3);
    assert_true(a->max_depth_m == b->max_depth_m);
    assert_int_equal(a->sinks, b->sinks);
}

/* The removal with its counts: the same bytes as pg_pits_remove, the same figures
 * (exactly: the sums run in the same order) as counting the input and the result on
 * their own, for every variant, with and without no-data cells. */
static void test_remove_counted(void **state) {
    (void)state;
    uint64_t with_depressions = 0;
    for (uint32_t seed = 300; seed < 340; seed++) {
        int w, h;
        pg_pits_topo t;
        pg_pits_opts o;
        float *dem = random_case(seed, &w, &h, &t, &o);
        size_t n = (size_t)w * h;
        if (seed % 5 == 3) { /* a no-data cell */
            o.has_nodata = true;
            o.nodata = -9999.0f;
            dem[hash32(seed, 3) % n] = -9999.0f;
        }
        float *a = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
        for (size_t v = 0; v < sizeof VARIANTS / sizeof *VARIANTS; v++) {
            o.method = VARIANTS[v].m;
            o.epsilon = VARIANTS[v].eps;
            o.descent = VARIANTS[v].descent;
            /* the plain fill's counts take w from the serial fill, or from the tiled
             * fill's flats afterwards (pits_meps_from_fill) */
            o.tile_rows = o.method == PG_PITS_FILL && !o.epsilon && seed % 2 ? 7 : 0;
            memcpy(a, dem, sizeof(float) * n);
            memcpy(b, dem, sizeof(float) * n);
            pg_pits_result ra, rb;
            assert_int_equal(pg_pits_remove(&t, a, &o, &ra, NULL), PG_OK);
            pg_pits_stats before, after, ref;
            assert_int_equal(pg_pits_remove_counted(&t, b, &o, NULL, &rb, &before, &after, NULL),
                             PG_OK);
            assert_memory_equal(a, b, sizeof(float) * n);
            assert_int_equal(ra.raised, rb.raised);
            assert_int_equal(ra.lowered, rb.lowered);
            assert_true(ra.max_raise == rb.max_raise && ra.max_lower == rb.max_lower);
            assert_int_equal(ra.sinks, rb.sinks);
            assert_int_equal(pg_pits_stats_compute(&t, dem, &o, NULL, &ref, NULL), PG_OK);
            assert_same_stats(&before, &ref);
            with_depressions += ref.depressions > 0;
            assert_int_equal(pg_pits_stats_compute(&t, a, &o, NULL, &ref, NULL), PG_OK);
            assert_same_stats(&after, &ref);
        }
        free(a);
        free(b);
        free(dem);
    }
    assert_true(with_depressions > 100);
}

/* Blocks of B x B cells, each its own grid, as the distributed pits lay out tiles:
 * a border cell's neighbours are those inside its block. */
enum { BLK = 9 };
static int block_border(const void *ctx, uint32_t id, uint32_t out[8]) {
    (void)ctx;
    const uint32_t b = id / (BLK * BLK), r = id % (BLK * BLK);
    const int x = (int)(r % BLK), y = (int)(r / BLK);
    int k = 0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            if ((dx || dy) && x + dx >= 0 && x + dx < BLK && y + dy >= 0 && y + dy < BLK)
                out[k++] = b * BLK * BLK + (uint32_t)((y + dy) * BLK + x + dx);
    return k;
}

/* Blocks as the distributed pits lay out tiles, each block its own grid. Without cells
 * after the blocks, the removal with its counts (whose certificate walks rows) and the
 * counts alone agree with each block counted as a grid. With such cells, whose
 * neighbours the topology cannot give, every entry point refuses and writes nothing:
 * the flood's seeding once asked the neighbours of those that were sinks, a read past
 * the end of its state array. The certificate's walk over the blocks' rows answers as
 * a cell-by-cell check through pg_pits_neighbours does, for closing orders with random
 * swaps, so a block's first or last row taken for an interior one shows. */
static void test_blocks_counted(void **state) {
    (void)state;
    enum { NB = 3, NCELLS = NB * BLK * BLK, EXTRA = 3 * BLK + 4 };
    pg_pits_topo t, g, x;
    assert_int_equal(pg_pits_topo_blocks(&t, BLK, NB, 0, block_border, NULL, NULL), PG_OK);
    assert_int_equal(pg_pits_topo_blocks(&x, BLK, NB, EXTRA, block_border, NULL, NULL), PG_OK);
    pg_pits_topo_grid(&g, BLK, BLK, NULL);
    int pitted = 0, certified_swaps = 0, refused_swaps = 0;
    float *xd = malloc(sizeof(float) * (NCELLS + EXTRA)),
          *xa = malloc(sizeof *xa * (NCELLS + EXTRA));
    float *off = calloc(NCELLS + EXTRA, sizeof *off);
    for (uint32_t seed = 700; seed < 712; seed++) {
        float *dem = malloc(sizeof(float) * NCELLS), *a = malloc(sizeof(float) * NCELLS);
        for (uint32_t i = 0; i < NCELLS; i++)
            dem[i] = 1.0f + (float)(hash32(seed, i) % 40);
        for (uint32_t b = 0; b < NB; b++) /* an outlet on each block's edge */
            dem[b * BLK * BLK + hash32(seed, 1000 + b) % BLK] = -3.0f;
        for (uint32_t i = 0; i < NCELLS + EXTRA; i++) /* the extra cells: sinks */
            xd[i] = i < NCELLS ? dem[i] : -1.0f;
        for (size_t v = 0; v < sizeof VARIANTS / sizeof *VARIANTS; v++) {
            pg_pits_opts o;
            pg_pits_opts_default(&o);
            o.has_sea_level = true;
            o.sea_level = 0;
            o.method = VARIANTS[v].m;
            o.epsilon = VARIANTS[v].eps;
            o.descent = VARIANTS[v].descent;
            pg_pits_stats before, after, ref, part;
            memcpy(a, dem, sizeof(float) * NCELLS);
            assert_int_equal(pg_pits_remove_counted(&t, a, &o, NULL, NULL, &before, &after, NULL),
                             PG_OK);
            assert_int_equal(after.depressions, 0);
            assert_int_equal(pg_pits_stats_compute(&t, a, &o, NULL, &ref, NULL), PG_OK);
            assert_int_equal(ref.depressions, 0);
            assert_int_equal(pg_pits_stats_compute(&t, dem, &o, NULL, &ref, NULL), PG_OK);
            assert_same_stats(&before, &ref);
            uint64_t deps = 0, cells = 0;
            double vol = 0, depth = 0;
            for (uint32_t b = 0; b < NB; b++) {
                assert_int_equal(
                    pg_pits_stats_compute(&g, dem + b * BLK * BLK, &o, NULL, &part, NULL), PG_OK);
                deps += part.depressions, cells += part.depression_cells;
                vol += part.depression_volume_m3;
                depth = fmax(depth, part.max_depth_m);
            }
            assert_int_equal(before.depressions, deps);
            assert_int_equal(before.depression_cells, cells);
            assert_true(fabs(before.depression_volume_m3 - vol) <= 1e-9 * (1 + vol));
            assert_true(before.max_depth_m == depth);
            pitted += deps > 0;
            if (o.method == PG_PITS_FILL && !o.epsilon && deps > 0) {
                /* the closing order certifies the fill through the blocks' rows */
                uint32_t *order = calloc(NCELLS, sizeof *order);
                uint8_t *sk = NULL;
                uint64_t ns = 0;
                memcpy(a, dem, sizeof(float) * NCELLS);
                assert_int_equal(pits_priority_flood_barnes2014(&t, a, &o, NULL, NULL, order),
                                 PG_OK);
                assert_int_equal(pits_begin(&t, a, &o, &sk, NULL, &ns, NULL), PG_OK);
                assert_true(pits_drains_by(&t, a, sk, NULL, order));
                assert_false(pits_drains_by(&t, dem, sk, NULL, order));
                for (uint32_t k = 0; k < 40; k++) { /* one swap each, cell by cell */
                    uint32_t i = hash32(seed, 5000 + k) % NCELLS,
                             j = hash32(seed, 6000 + k) % NCELLS;
                    uint32_t oi = order[i];
                    order[i] = order[j], order[j] = oi;
                    const float *hs = k % 2 ? dem : a;
                    int ref = 1;
                    for (uint32_t c = 0; c < NCELLS && ref; c++) {
                        if (sk[c] != PITS_OPEN) continue;
                        uint32_t nb[8];
                        int nk = pg_pits_neighbours(&t, c, nb), ok = 0;
                        for (int q = 0; q < nk; q++)
                            ok |= sk[nb[q]] != PITS_OPEN ||
                                  (order[nb[q]] < order[c] && hs[nb[q]] <= hs[c]);
                        ref = ok;
                    }
                    assert_int_equal(pits_drains_by(&t, hs, sk, NULL, order), ref);
                    certified_swaps += ref, refused_swaps += !ref;
                    order[j] = order[i], order[i] = oi; /* back */
                }
                free(sk), free(order);
            }

            memcpy(xa, xd, sizeof(float) * (NCELLS + EXTRA));
            pg_error e = {0};
            assert_int_equal(pg_pits_remove(&x, xa, &o, NULL, &e), PG_ERR_BADINPUT);
            assert_non_null(strstr(e.msg, "after its blocks"));
            assert_int_equal(pg_pits_remove_counted(&x, xa, &o, NULL, NULL, &before, &after, NULL),
                             PG_ERR_BADINPUT);
            assert_int_equal(pg_pits_stats_compute(&x, xa, &o, NULL, &ref, NULL), PG_ERR_BADINPUT);
            assert_int_equal(pg_pits_correct_offsets(&x, xa, off, &o, NULL, NULL), PG_ERR_BADINPUT);
            assert_memory_equal(xa, xd, sizeof(float) * (NCELLS + EXTRA));
        }
        free(dem), free(a);
    }
    for (uint32_t i = 0; i < NCELLS + EXTRA; i++)
        assert_true(off[i] == 0);
    free(xd), free(xa), free(off);
    assert_true(pitted > 60); /* the blocks had depressions to count */
    print_message("blocks: swapped closing orders: %d certify, %d do not\n", certified_swaps,
                  refused_swaps);
    assert_true(certified_swaps > 0 && refused_swaps > 0);
    { /* no blocks, only cells after them: refused too */
        pg_pits_topo z;
        assert_int_equal(pg_pits_topo_blocks(&z, BLK, 0, BLK * BLK, block_border, NULL, NULL),
                         PG_OK);
        float *zh = calloc(BLK * BLK, sizeof *zh);
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        assert_int_equal(pg_pits_remove(&z, zh, &o, NULL, NULL), PG_ERR_BADINPUT);
        free(zh);
    }
}

/* A W x H grid whose sinks are the cells at or below sea_level (closed edges). */
static void sea_grid(pg_pits_topo *t, pg_pits_opts *o, int w, int h, double sea_level) {
    pg_pits_topo_grid(t, (uint32_t)w, (uint32_t)h, NULL);
    pg_pits_opts_default(o);
    o->has_sea_level = true;
    o->sea_level = sea_level;
}

/* A depression's volume and depth are the water the minimal fill holds, not the
 * epsilon-fill's ulps on top: here a flat B one ulp above flat A drains through A, so
 * B's epsilon-surface rises past A's ulps, yet a pit in B 1 m deep holds exactly 1 m
 * of water. The count after a tiled plain fill takes
 * the epsilon-surface from the fill's flats, whose guess fails on this grid (B must
 * rise past A's ulps, not start at B's own height); it must then count in full and
 * still find none. */
static void test_stats_fill_volume(void **state) {
    (void)state;
    enum { W = 24, H = 3 };
    const float s = 1000.0f, s1 = nextafterf(1000.0f, INFINITY);
    float dem[W * H];
    for (int i = 0; i < W * H; i++)
        dem[i] = 2000.0f; /* walls, above both flats */
    dem[W + 0] = 0.0f;    /* the sea */
    for (int x = 1; x <= 10; x++)
        dem[W + x] = s; /* flat A */
    for (int x = 11; x <= 20; x++)
        dem[W + x] = s1;     /* flat B, draining through A */
    dem[W + 15] = s1 - 1.0f; /* the pit */
    pg_pits_topo t;
    pg_pits_opts o;
    sea_grid(&t, &o, W, H, 0.5);
    /* the guess from the fill's flats is refused on this grid */
    float fill[W * H], w[W * H], eps[W * H];
    memcpy(fill, dem, sizeof fill);
    o.method = PG_PITS_FILL;
    o.epsilon = false;
    assert_int_equal(pg_pits_remove(&t, fill, &o, NULL, NULL), PG_OK);
    uint8_t *sk = NULL;
    uint64_t ns = 0;
    assert_int_equal(pits_begin(&t, fill, &o, &sk, NULL, &ns, NULL), PG_OK);
    assert_int_not_equal(pits_meps_from_fill(&t, fill, sk, w), 0);
    free(sk);
    /* the epsilon-fill lifts the pit past all of A's ulps; the water is 1 m deep */
    memcpy(eps, dem, sizeof eps);
    o.epsilon = true;
    assert_int_equal(pg_pits_remove(&t, eps, &o, NULL, NULL), PG_OK);
    assert_true(eps[W + 15] > s1 && fill[W + 15] == s1);
    const double water = (double)s1 - (double)dem[W + 15];
    pg_pits_stats st;
    pg_pits_area area = {NULL, NULL, NULL, 4.0};
    assert_int_equal(pg_pits_stats_compute(&t, dem, &o, &area, &st, NULL), PG_OK);
    assert_int_equal(st.depressions, 1);
    assert_int_equal(st.depression_cells, 1);
    assert_true(st.depression_volume_m3 == 4.0 * water);
    assert_true(st.max_depth_m == water);
    /* the counted fill, serial and tiled (whose certificate refuses here), agree */
    for (int tiled = 0; tiled < 2; tiled++) {
        pg_pits_stats before, after;
        o.epsilon = false;
        o.tile_rows = tiled ? 2 : 0;
        memcpy(fill, dem, sizeof fill);
        assert_int_equal(pg_pits_remove_counted(&t, fill, &o, &area, NULL, &before, &after, NULL),
                         PG_OK);
        assert_int_equal(before.depressions, 1);
        assert_true(before.depression_volume_m3 == st.depression_volume_m3);
        assert_true(before.max_depth_m == st.max_depth_m);
        assert_int_equal(after.depressions, 0);
        assert_int_equal(after.sinks, before.sinks);
    }
}

/* The epsilon-surface that the counts take from a plain fill (pits_meps_from_fill):
 * one ulp per step from the NEAREST exit of each flat. Checked bit for bit against
 * the epsilon-fill on a corridor with an exit at each end (a search from the first
 * exit alone would put the far end 17 ulps up, not 1) and on grids of wide integer
 * flats, where the guess must check out. */
static void check_fill_eps(const pg_pits_topo *t, const float *dem, pg_pits_opts o, size_t n,
                           int *exact) {
    float *a = malloc(sizeof(float) * n), *e = malloc(sizeof(float) * n);
    float *w2 = malloc(sizeof(float) * n);
    o.method = PG_PITS_FILL;
    o.epsilon = false;
    memcpy(a, dem, sizeof(float) * n);
    assert_int_equal(pits_priority_flood_barnes2014(t, a, &o, NULL, NULL, NULL), PG_OK);
    o.epsilon = true;
    memcpy(e, dem, sizeof(float) * n);
    assert_int_equal(pg_pits_remove(t, e, &o, NULL, NULL), PG_OK);
    uint8_t *sk = NULL;
    uint64_t ns = 0;
    assert_int_equal(pits_begin(t, a, &o, &sk, NULL, &ns, NULL), PG_OK);
    *exact = pits_meps_from_fill(t, a, sk, w2) == 0;
    free(sk);
    if (*exact) assert_memory_equal(w2, e, sizeof(float) * n);
    free(a), free(e), free(w2);
}

/* The minimal fill that the epsilon fill gives along its own tree
 * (pits_minimal_eps_planchon2002_fill): the plain fill's bytes, always. Where the
 * epsilon-surface's cheapest path crosses ground one ulp above the fill (an exit one
 * ulp higher than the rim, beside a long flat) the tree's answer is too high; the
 * check catches it, the repair (pits_fill_repair) lowers it, and the counts agree (the
 * grid built by hand below, and random grids whose flats have cells one ulp higher).
 * Soille's flood gives the minimal fill as its running maximum
 * (pits_breach_soille2004_fill), and so does Lindsay's hybrid flood
 * (pits_hybrid_lindsay2016_fill): always exact. */
static void test_eps_fill_gives_fill(void **state) {
    (void)state;
    int exacts = 0, cases = 0, exact = 0, carved = 0;
    pg_pits_topo t;
    pg_pits_opts o;
    for (uint32_t seed = 600; seed < 630; seed++, cases++) {
        int w = 40 + (int)(hash32(seed, 1) % 120), h = 30 + (int)(hash32(seed, 2) % 90);
        size_t n = (size_t)w * h;
        float *d = malloc(sizeof(float) * n), *a = malloc(sizeof(float) * n);
        float *b = malloc(sizeof(float) * n), *f = malloc(sizeof(float) * n);
        for (size_t i = 0; i < n; i++) {
            int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
            double v = 40.0 * sin(0.05 * x + seed) * cos(0.07 * y) +
                       10.0 * (hash32(seed, (uint32_t)i) / 4294967296.0);
            d[i] = seed % 2 ? (float)v : (float)floor(v / 8) * 8;
            /* flats with cells one ulp higher: exits that differ by less than the epsilon
             * ramp to them, where the epsilon tree's fill needs the repair */
            if (seed % 4 == 2 && hash32(seed, (uint32_t)i + 7777u) % 8 == 0)
                d[i] = nextafterf(d[i], INFINITY);
        }
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        pg_pits_opts_default(&o);
        set_sinks(&o, seed);
        o.method = PG_PITS_FILL;
        o.epsilon = false;
        memcpy(a, d, sizeof(float) * n);
        assert_int_equal(pg_pits_remove(&t, a, &o, NULL, NULL), PG_OK);
        o.epsilon = true;
        memcpy(b, d, sizeof(float) * n);
        assert_int_equal(pits_minimal_eps_planchon2002_fill(&t, b, &o, NULL, d, f, &exact, NULL),
                         PG_OK);
        assert_int_equal(exact, 1);
        assert_memory_equal(a, f, sizeof(float) * n);
        float *plain = a;
        a = malloc(sizeof(float) * n);
        memcpy(a, d, sizeof(float) * n);
        assert_int_equal(pg_pits_remove(&t, a, &o, NULL, NULL), PG_OK);
        assert_memory_equal(a, b, sizeof(float) * n); /* the epsilon fill is unchanged */
        /* Soille's flood gives it with no check at all: always the same bytes (these
         * heights have no -0; with one, only the sign of a zero fill may differ) */
        o.method = PG_PITS_BREACH;
        o.epsilon = seed % 3 == 0;
        memcpy(b, d, sizeof(float) * n);
        assert_int_equal(pits_breach_soille2004_fill(&t, b, &o, NULL, f, NULL), PG_OK);
        assert_memory_equal(plain, f, sizeof(float) * n);
        /* Lindsay's hybrid flood too, whatever it carves or fills; its result unchanged */
        o.method = PG_PITS_HYBRID;
        o.max_depth = seed % 3 ? 15.0 : INFINITY;
        o.max_length = (double)(seed % 4) * 6; /* 0: the plain fill */
        memcpy(a, d, sizeof(float) * n);
        assert_int_equal(pits_hybrid_lindsay2016(&t, a, &o, NULL, NULL), PG_OK);
        memcpy(b, d, sizeof(float) * n);
        pg_pits_result rl;
        assert_int_equal(pits_hybrid_lindsay2016_fill(&t, b, &o, &rl, f, NULL), PG_OK);
        assert_memory_equal(a, b, sizeof(float) * n);
        assert_memory_equal(plain, f, sizeof(float) * n);
        carved += rl.breaches > 0;
        /* the descent tree's floods: the breach unchanged, its fill the plain fill's
         * bytes (without epsilon always; with it whenever the check passes) */
        for (int eps = 0; eps < 2; eps++) {
            o.method = seed % 4 < 2 ? PG_PITS_BREACH : PG_PITS_HYBRID;
            o.descent = true;
            o.epsilon = eps;
            int dex = -1;
            memcpy(a, d, sizeof(float) * n);
            assert_int_equal(pits_breach_descent(&t, a, &o, NULL, NULL), PG_OK);
            memcpy(b, d, sizeof(float) * n);
            assert_int_equal(pits_breach_descent_fill(&t, b, &o, NULL, f, &dex, NULL), PG_OK);
            assert_memory_equal(a, b, sizeof(float) * n);
            assert_int_equal(dex, 1);
            assert_memory_equal(plain, f, sizeof(float) * n);
            exacts += eps && dex;
            cases += eps;
            o.descent = false;
        }
        free(plain);
        exacts += exact;
        free(d), free(a), free(b), free(f);
    }
    assert_int_equal(exacts, cases);
    assert_true(carved >= 10); /* Lindsay's channels were carved, not only filled */
    /* sea | X2 = up(s) | P | X1 .. X10 = s | sea: P's cheapest epsilon path leaves over
     * X2 (up(s) + 1 ulp against s + 10 ulps over the flat), its fill is s (over X1) */
    enum { W = 14, H = 3 };
    const float s = 500.0f;
    float dem[W * H], f[W * H], e[W * H];
    for (int i = 0; i < W * H; i++)
        dem[i] = 2000.0f;
    dem[W + 0] = dem[W + 13] = -100.0f;
    dem[W + 1] = nextafterf(s, INFINITY);
    dem[W + 2] = 1.0f;
    for (int x = 3; x <= 12; x++)
        dem[W + x] = s;
    sea_grid(&t, &o, W, H, -50.0);
    o.method = PG_PITS_FILL;
    o.epsilon = true;
    memcpy(e, dem, sizeof e);
    assert_int_equal(pits_minimal_eps_planchon2002_fill(&t, e, &o, NULL, dem, f, &exact, NULL),
                     PG_OK);
    /* P's epsilon path leaves over X2, so its tree's fill was up(s); repaired to s */
    assert_true(e[W + 2] == nextafterf(nextafterf(s, INFINITY), INFINITY));
    assert_int_equal(exact, 1);
    assert_true(f[W + 2] == s);
    float a[W * H];
    memcpy(a, dem, sizeof a);
    o.epsilon = false;
    assert_int_equal(pg_pits_remove(&t, a, &o, NULL, NULL), PG_OK);
    assert_true(a[W + 2] == s);
    o.method = PG_PITS_BREACH;
    memcpy(e, dem, sizeof e);
    assert_int_equal(pits_breach_soille2004_fill(&t, e, &o, NULL, f, NULL), PG_OK);
    assert_memory_equal(a, f, sizeof a); /* Soille's flood: right here too */
    o.method = PG_PITS_HYBRID;           /* and Lindsay's */
    memcpy(e, dem, sizeof e);
    assert_int_equal(pits_hybrid_lindsay2016_fill(&t, e, &o, NULL, f, NULL), PG_OK);
    assert_memory_equal(a, f, sizeof a);
    o.method = PG_PITS_BREACH; /* the descent tree's epsilon flood refuses it as well */
    o.descent = true;
    o.epsilon = true;
    memcpy(e, dem, sizeof e);
    assert_int_equal(pits_breach_descent_fill(&t, e, &o, NULL, f, &exact, NULL), PG_OK);
    assert_int_equal(exact, 1); /* repaired as well */
    assert_memory_equal(a, f, sizeof a);
    pg_pits_stats before, after, ref;
    for (int m = 0; m < 2; m++) { /* and the counts agree */
        o.method = m ? PG_PITS_BREACH : PG_PITS_FILL;
        o.descent = m;
        memcpy(e, dem, sizeof e);
        assert_int_equal(pg_pits_remove_counted(&t, e, &o, NULL, NULL, &before, &after, NULL),
                         PG_OK);
        assert_int_equal(pg_pits_stats_compute(&t, dem, &o, NULL, &ref, NULL), PG_OK);
        assert_same_stats(&before, &ref);
        assert_int_equal(before.depression_cells, 1);
        assert_int_equal(after.depressions, 0);
    }
}

static void test_fill_eps_guess(void **state) {
    (void)state;
    enum { W = 20, H = 3 };
    float dem[W * H];
    for (int i = 0; i < W * H; i++)
        dem[i] = 100.0f;
    dem[W + 0] = dem[W + W - 1] = 0.0f; /* the sea at both ends */
    for (int x = 1; x < W - 1; x++)
        dem[W + x] = 10.0f;
    dem[W + 9] = 5.0f; /* a pit in the corridor */
    pg_pits_topo t;
    pg_pits_opts o;
    sea_grid(&t, &o, W, H, 0.5);
    int exact = 0, exacts = 0, cases = 0;
    check_fill_eps(&t, dem, o, W * H, &exact);
    assert_int_equal(exact, 1);
    for (uint32_t seed = 500; seed < 530; seed++, cases++) {
        int w = 40 + (int)(hash32(seed, 1) % 120), h = 30 + (int)(hash32(seed, 2) % 90);
        float *d = malloc(sizeof(float) * (size_t)w * h);
        for (int i = 0; i < w * h; i++) {
            int x = i % w, y = i / w;
            double v = 40.0 * sin(0.05 * x + seed) * cos(0.07 * y) +
                       10.0 * (hash32(seed, (uint32_t)i) / 4294967296.0);
            d[i] = (float)floor(v / 8) * 8; /* wide flats with many exits */
        }
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        pg_pits_opts_default(&o);
        set_sinks(&o, seed);
        check_fill_eps(&t, d, o, (size_t)w * h, &exact);
        exacts += exact;
        free(d);
    }
    assert_true(exacts >= cases - 2); /* integer flats: the guess holds */
}

/* The certificate that spares the count after a removal: whenever it holds, the
 * grid has no depression (raw grids with depressions must fail it); it holds on every
 * epsilon result, and on a plain fill with the epsilon-surface as the potential. */
static void test_drain_certificate(void **state) {
    (void)state;
    uint64_t refused = 0, plain_ok = 0, plain = 0;
    for (uint32_t seed = 400; seed < 460; seed++) {
        int w = 1 + (int)(hash32(seed, 1) % 30), h = 1 + (int)(hash32(seed, 2) % 30);
        size_t n = (size_t)w * h;
        float *dem = random_dem(seed, w, h), *out = malloc(sizeof(float) * n),
              *eps = malloc(sizeof(float) * n);
        pg_pits_topo t;
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        set_sinks(&o, seed);
        o.method = PG_PITS_FILL;
        memcpy(eps, dem, sizeof(float) * n);
        assert_int_equal(pg_pits_remove(&t, eps, &o, NULL, NULL), PG_OK);
        /* the order in which the serial plain fill closes the cells */
        uint32_t *order = calloc(n, sizeof(uint32_t));
        float *fl = malloc(sizeof(float) * n);
        memcpy(fl, dem, sizeof(float) * n);
        o.epsilon = false;
        assert_int_equal(pits_priority_flood_barnes2014(&t, fl, &o, NULL, NULL, order), PG_OK);
        for (size_t v = 0; v <= sizeof VARIANTS / sizeof *VARIANTS; v++) {
            memcpy(out, dem, sizeof(float) * n); /* v == count: the raw grid */
            if (v < sizeof VARIANTS / sizeof *VARIANTS) {
                o.method = VARIANTS[v].m;
                o.epsilon = VARIANTS[v].eps;
                o.descent = VARIANTS[v].descent;
                assert_int_equal(pg_pits_remove(&t, out, &o, NULL, NULL), PG_OK);
            }
            pg_pits_stats st;
            assert_int_equal(pg_pits_stats_compute(&t, out, &o, NULL, &st, NULL), PG_OK);
            float *c = malloc(sizeof(float) * n);
            memcpy(c, out, sizeof(float) * n);
            uint8_t *sk = NULL;
            uint64_t ns = 0;
            assert_int_equal(pits_begin(&t, c, &o, &sk, NULL, &ns, NULL), PG_OK);
            int by_self = pits_drains_by(&t, c, sk, c, NULL);
            int by_eps = pits_drains_by(&t, c, sk, eps, NULL);
            int by_order = pits_drains_by(&t, c, sk, NULL, order);
            if (by_self || by_eps || by_order) assert_int_equal(st.depressions, 0);
            if (st.depressions) refused++;
            /* (with the lowest cell as the only sink, carving may move it) */
            if (v < sizeof VARIANTS / sizeof *VARIANTS && VARIANTS[v].eps &&
                (o.has_sea_level || o.open_edges))
                assert_true(by_self);
            if (v < sizeof VARIANTS / sizeof *VARIANTS && !VARIANTS[v].eps &&
                VARIANTS[v].m == PG_PITS_FILL) {
                plain++, plain_ok += by_eps;
                assert_true(by_order); /* the serial fill's own certificate */
                /* the epsilon-surface from the fill's flats: exact, no flood */
                float *wf = malloc(sizeof(float) * n);
                assert_int_equal(pits_meps_from_fill(&t, c, sk, wf), 0);
                for (size_t i = 0; i < n; i++)
                    if (sk[i] == PITS_OPEN) assert_memory_equal(&wf[i], &eps[i], sizeof(float));
                free(wf);
            }
            free(sk);
            free(c);
        }
        free(order);
        free(fl);
        free(out);
        free(eps);
        free(dem);
    }
    /* a flat pit (2 x 2 cells at 1 inside a plateau at 10) is a depression, though
     * each of its cells has a neighbour no higher */
    float flat[36];
    for (int i = 0; i < 36; i++)
        flat[i] = 10.0f;
    flat[14] = flat[15] = flat[20] = flat[21] = 1.0f;
    pg_pits_topo t;
    pg_pits_topo_grid(&t, 6, 6, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.open_edges = true;
    uint8_t *sk = NULL;
    uint64_t ns = 0;
    assert_int_equal(pits_begin(&t, flat, &o, &sk, NULL, &ns, NULL), PG_OK);
    assert_false(pits_drains_by(&t, flat, sk, flat, NULL));
    uint32_t up[36], down[36]; /* whatever the potential */
    for (uint32_t i = 0; i < 36; i++)
        up[i] = i, down[i] = 35 - i;
    assert_false(pits_drains_by(&t, flat, sk, NULL, up));
    assert_false(pits_drains_by(&t, flat, sk, NULL, down));
    float wf[36]; /* nor is it taken for a fill whose flats all drain */
    assert_int_not_equal(pits_meps_from_fill(&t, flat, sk, wf), 0);
    free(sk);
    assert_true(refused > 30);      /* grids with depressions were offered */
    assert_true(plain_ok == plain); /* the plain fill's count needs no search here */
}

/* The radix heap under a flood that merges it with a FIFO (the minimal epsilon-surface):
 * asking for the smallest key must not raise the heap's floor, since the flood may then
 * take a smaller value from its FIFO and push keys between the last key popped and the
 * heap's smallest. Random pushes (never below the last key popped), peeks and pops
 * against a sorted reference: every peek and pop gives the true smallest key. */
static int cmp_u32(const void *a, const void *b) {
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* The repair of a tree's fill (pits_fill_repair): the fill along a random tree towards
 * the sinks - each cell's parent a neighbour drawn at random among those already joined
 * - is the highest ground on one path, never below the minimal fill; the repair lowers
 * it to the plain fill's bytes, on grids with and without flats, whatever the tree. */
static void test_fill_repair_random_trees(void **state) {
    (void)state;
    int repaired = 0;
    for (uint32_t seed = 700; seed < 740; seed++) {
        int w, h;
        pg_pits_topo t;
        pg_pits_opts o;
        float *dem = random_case(seed, &w, &h, &t, &o);
        o.has_nodata = false;
        const size_t n = (size_t)w * h;
        float *plain = malloc(sizeof(float) * n), *f = malloc(sizeof(float) * n);
        uint8_t *joined = calloc(n, 1), *now = malloc(n);
        memcpy(plain, dem, sizeof(float) * n);
        o.method = PG_PITS_FILL;
        o.epsilon = false;
        assert_int_equal(pg_pits_remove(&t, plain, &o, NULL, NULL), PG_OK);
        uint8_t *st = NULL;
        uint64_t nsinks = 0;
        assert_int_equal(pits_begin(&t, dem, &o, &st, NULL, &nsinks, NULL), PG_OK);
        for (size_t i = 0; i < n; i++)
            if (st[i] >= PITS_SINK) joined[i] = 1, f[i] = dem[i];
        /* join the cells in rounds, each to a random neighbour joined in an earlier round */
        for (int round = 0, left = 1; left; round++) {
            left = 0;
            memcpy(now, joined, n);
            for (size_t i = 0; i < n; i++) {
                if (joined[i]) continue;
                uint32_t nb[8], in[8];
                int k = pg_pits_neighbours(&t, (uint32_t)i, nb), m = 0;
                for (int j = 0; j < k; j++)
                    if (joined[nb[j]]) in[m++] = nb[j];
                if (!m) {
                    left = 1;
                    continue;
                }
                const uint32_t p = in[hash32(seed * 131u + (uint32_t)round, (uint32_t)i) % m];
                /* a sink takes water at any height: its child's path tops out at itself */
                f[i] = st[p] >= PITS_SINK ? dem[i] : pits_maxf(dem[i], f[p]);
                now[i] = 1;
            }
            memcpy(joined, now, n);
        }
        size_t above = 0;
        for (size_t i = 0; i < n; i++) {
            assert_true(f[i] >= plain[i]);
            above += f[i] != plain[i];
        }
        repaired += above > 0;
        assert_int_equal(pits_fill_repair(&t, dem, st, f), 0);
        assert_memory_equal(f, plain, sizeof(float) * n);
        free(st), free(dem), free(plain), free(f), free(joined), free(now);
    }
    assert_true(repaired >= 30); /* most trees were wrong somewhere before the repair */
}

static void test_rheap_order(void **state) {
    (void)state;
    for (uint32_t seed = 0; seed < 40; seed++) {
        pits_rheap r = {0};
        uint32_t ref[4096], n = 0, floor_ = 0, peeks = 0, below = 0;
        for (uint32_t op = 0; op < 4000; op++) {
            uint32_t kind = hash32(seed, 3 * op) % 8, span = 1u << (hash32(seed, 3 * op + 1) % 24);
            if (kind < 4 && n < 4096) { /* push, at least the last key popped */
                uint32_t key = floor_ + hash32(seed, 3 * op + 2) % span;
                below += n && key < ref[0];
                pits_rheap_push(&r, key, op);
                ref[n++] = key;
                qsort(ref, n, sizeof *ref, cmp_u32);
            } else if (kind < 6 && n) {
                assert_int_equal(pits_rheap_top_key(&r), ref[0]);
                peeks++;
            } else if (n) {
                uint64_t e = pits_rheap_pop(&r);
                assert_int_equal((uint32_t)(e >> 32), ref[0]);
                floor_ = ref[0];
                memmove(ref, ref + 1, --n * sizeof *ref);
            }
            assert_int_equal(r.size, n);
        }
        assert_true(peeks > 0 && below > 0); /* the case that matters happened */
        pits_rheap_free(&r);
    }
}

/* No-data cells: refused without a stated value; with one, left alone as outlets. */
static void test_bad_input_and_nodata(void **state) {
    (void)state;
    float dem[25];
    for (int i = 0; i < 25; i++)
        dem[i] = 5.0f;
    dem[12] = 1.0f; /* centre pit */
    dem[3] = NAN;
    pg_pits_topo t;
    pg_pits_topo_grid(&t, 5, 5, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    pg_error err = {0};
    float a[25];
    memcpy(a, dem, sizeof a);
    assert_int_equal(pg_pits_remove(&t, a, &o, NULL, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "no-data"));
    o.has_nodata = true;
    o.nodata = -9999.0f;
    dem[3] = -9999.0f;
    memcpy(a, dem, sizeof a);
    assert_int_equal(pg_pits_remove(&t, a, &o, NULL, NULL), PG_OK);
    assert_true(a[3] == -9999.0f);
    int below = 0; /* breached: a channel below the pit runs to the no-data hole */
    for (int i = 0; i < 25; i++)
        below += a[i] < 1.0f && i != 3;
    assert_true(below >= 1);
    o.max_depth = -1;
    pg_error_clear(&err);
    assert_int_equal(pg_pits_remove(&t, a, &o, NULL, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "--max-depth"));
    pg_pits_method m;
    assert_false(pg_pits_method_parse("carve", &m));
    assert_true(pg_pits_method_parse("hybrid", &m) && m == PG_PITS_HYBRID);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_methods_drain),
        cmocka_unit_test(test_exact_fill),
        cmocka_unit_test(test_hybrid_limits),
        cmocka_unit_test(test_hybrid_length_limit),
        cmocka_unit_test(test_thread_invariance),
        cmocka_unit_test(test_stats),
        cmocka_unit_test(test_stats_reference),
        cmocka_unit_test(test_bad_input_and_nodata),
        cmocka_unit_test(test_remove_counted),
        cmocka_unit_test(test_fill_eps_guess),
        cmocka_unit_test(test_eps_fill_gives_fill),
        cmocka_unit_test(test_drain_certificate),
        cmocka_unit_test(test_stats_fill_volume),
        cmocka_unit_test(test_eps_by_fill),
        cmocka_unit_test(test_blocks_counted),
        cmocka_unit_test(test_rheap_order),
        cmocka_unit_test(test_fill_repair_random_trees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
