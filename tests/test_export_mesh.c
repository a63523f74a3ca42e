/* test_export_mesh.c - the globe mesh and the EXR, on the real Earth reprojected onto a
 * small planet: seams are watertight (coincident vertices of different faces are
 * bit-identical: gap exactly 0, normals too), normals are unit and tangents
 * orthogonal to them, vertices are displaced by the exaggerated height (the
 * Antarctic plateau stands out, the Arctic Ocean lies at sea level), the default
 * mesh is about 200k triangles, options are checked, and the multi-part EXR reads
 * back equal to the heights (in our reader, exrheader and oiiotool); the globe renders
 * shade the relief (a hill is lit on its side towards the light); planet.glb embeds
 * the albedo PNGs the planet's save kept, and encodes the same bytes itself. */
#include "export_fixture.h"

#include "pg_export_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct vkey {
    int L[3];
    int face;
    uint32_t v;
} vkey;

static int cmp_key(const void *a, const void *b) {
    const vkey *x = a, *y = b;
    for (int c = 0; c < 3; c++)
        if (x->L[c] != y->L[c]) return x->L[c] < y->L[c] ? -1 : 1;
    return x->face - y->face;
}

/* Group the vertices of all faces by their cube lattice point (computed here from the
 * face frames, independently of the exporter) and measure coincident pairs. */
static void check_watertight(const pg_export_mesh *mesh) {
    int m = mesh->m, w = m + 1;
    size_t total = 6 * (size_t)mesh->nv;
    vkey *k = malloc(total * sizeof *k);
    for (int f = 0; f < 6; f++) {
        int n[3], eu[3], ev[3];
        pg_cube_face_frame(f, n, eu, ev);
        for (int j = 0; j <= m; j++)
            for (int i = 0; i <= m; i++) {
                vkey *e = &k[(size_t)f * mesh->nv + (size_t)j * w + i];
                for (int c = 0; c < 3; c++)
                    e->L[c] = m * n[c] + (2 * i - m) * eu[c] + (2 * j - m) * ev[c];
                e->face = f, e->v = (uint32_t)(j * w + i);
            }
    }
    qsort(k, total, sizeof *k, cmp_key);
    size_t distinct = 0, coincident = 0;
    double gap = 0, ngap = 0;
    for (size_t a = 0; a < total; a++) {
        if (a == 0 || memcmp(k[a].L, k[a - 1].L, sizeof k[a].L) != 0) {
            distinct++;
            continue;
        }
        const float *p0 = mesh->pos[k[a - 1].face] + 3 * k[a - 1].v;
        const float *p1 = mesh->pos[k[a].face] + 3 * k[a].v;
        const float *n0 = mesh->nrm[k[a - 1].face] + 3 * k[a - 1].v;
        const float *n1 = mesh->nrm[k[a].face] + 3 * k[a].v;
        for (int c = 0; c < 3; c++) {
            gap = fmax(gap, fabs((double)p0[c] - p1[c]));
            ngap = fmax(ngap, fabs((double)n0[c] - n1[c]));
        }
        coincident++;
    }
    printf("distinct vertices %zu, coincident pairs %zu, max gap %g m, normal gap %g\n", distinct,
           coincident, gap, ngap);
    assert_int_equal(distinct, 6 * (size_t)m * m + 2);          /* Euler: V = 6 m^2 + 2 */
    assert_int_equal(coincident, 12 * (size_t)(m - 1) + 8 * 2); /* edges, corners */
    assert_true(gap == 0.0);
    assert_true(ngap == 0.0);
    free(k);
}

static void check_frames(const pg_export_mesh *mesh) {
    for (int f = 0; f < 6; f++)
        for (uint32_t v = 0; v < mesh->nv; v++) {
            const float *n = mesh->nrm[f] + 3 * v, *t = mesh->tan[f] + 4 * v;
            double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            double lt = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
            assert_true(fabs(ln - 1) < 1e-5 && fabs(lt - 1) < 1e-5);
            assert_true(fabs(n[0] * t[0] + n[1] * t[1] + n[2] * t[2]) < 1e-5);
            assert_true(t[3] == 1.0f); /* right-handed frames: bitangent = +v */
            /* outward: the normal points away from the centre */
            const float *p = mesh->pos[f] + 3 * v;
            assert_true(n[0] * p[0] + n[1] * p[1] + n[2] * p[2] > 0);
        }
}

static void test_mesh_watertight_and_displaced(void **s) {
    (void)s;
    pg_planet p;
    fixture_earth(&p, 2, 64);
    pg_error err = {0};
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, p.projection, p.tiles, p.tile_size, &err), PG_OK);
    pg_export_mesh mesh;
    assert_int_equal(pg_export_mesh_build(&p, &g, 32, 10.0, &mesh, &err), PG_OK);
    check_watertight(&mesh);
    check_frames(&mesh);
    /* pole vertices (face centres): Arctic Ocean at sea level, Antarctica kilometres up */
    double b = p.ellipsoid.a * (1 - p.ellipsoid.f);
    uint32_t c = 16 * 33 + 16;
    double zn = mesh.pos[PG_CUBE_FACE_PZ][3 * c + 2], zs = -mesh.pos[PG_CUBE_FACE_NZ][3 * c + 2];
    printf("north pole %.1f m, south pole %.1f m above the ellipsoid (10x)\n", zn - b, zs - b);
    assert_true(fabs(zn - b - 10 * p.sea_level) < 1.0);
    assert_true(zs - b > 10 * 2000.0 && zs - b < 10 * 4500.0);
    pg_export_mesh_free(&mesh);
    /* the same on the equal-area projection, whose seams are not separable */
    p.projection = PG_CUBE_EQUALAREA;
    assert_int_equal(pg_cube_grid_init(&g, p.projection, p.tiles, p.tile_size, &err), PG_OK);
    assert_int_equal(pg_export_mesh_build(&p, &g, 16, 10.0, &mesh, &err), PG_OK);
    check_watertight(&mesh);
    pg_export_mesh_free(&mesh);
    pg_planet_free(&p);
}

static void test_options_checked(void **s) {
    (void)s;
    pg_export_opts o;
    pg_export_opts_default(&o);
    pg_error err = {0};
    /* default planet: 128 quads per face edge, 196608 triangles */
    assert_int_equal(pg_export_default_mesh_res(4, 256), 128);
    assert_int_equal(pg_export_check_opts(&o, 4, 256, &err), PG_OK);
    assert_int_equal(pg_export_default_mesh_res(8, 512), 128);
    const int bad_res[] = {100, 6, 2048 + 4, 2};
    for (int i = 0; i < 4; i++) {
        o.mesh_res = bad_res[i];
        pg_error_clear(&err);
        assert_int_equal(pg_export_check_opts(&o, 4, 256, &err), PG_ERR_BADINPUT);
        assert_non_null(strstr(err.msg, "--mesh-res"));
    }
    o.mesh_res = 0;
    const double bad_x[] = {-1, 1e6, NAN};
    for (int i = 0; i < 3; i++) {
        o.exaggeration = bad_x[i];
        pg_error_clear(&err);
        assert_int_equal(pg_export_check_opts(&o, 4, 256, &err), PG_ERR_BADINPUT);
        assert_non_null(strstr(err.msg, "--exaggeration"));
    }
    pg_export_texture_format tf;
    pg_error_clear(&err);
    assert_int_equal(pg_export_texture_format_parse("gif", "--texture-format", &tf, &err),
                     PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "--texture-format 'gif'"));
    assert_int_equal(pg_export_texture_format_parse("jpeg", "--texture-format", &tf, &err), PG_OK);
    assert_int_equal(tf, PG_EXPORT_TEXTURE_JPEG);
}

static void test_exr_roundtrip(void **s) {
    (void)s;
    pg_planet p;
    fixture_earth(&p, 2, 32);
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.glb = o.previews = false;
    char dir[1024];
    pg_test_scratch_dir("export_exr", dir, sizeof dir);
    pg_planet_dir_paths st = {.dir = dir};
    pg_error err = {0};
    /* an exaggeration whose relief passes a quarter of the radius is refused */
    o.exaggeration = 900;
    assert_int_equal(pg_export_write(&p, &o, pg_planet_dir_path, &st, NULL, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "quarter of the"));
    o.exaggeration = 10;
    pg_error_clear(&err);
    pg_export_result r;
    assert_int_equal(pg_export_write(&p, &o, pg_planet_dir_path, &st, &r, &err), PG_OK);
    assert_int_equal(r.nfiles, 1);
    char path[1300];
    snprintf(path, sizeof path, "%s/height.exr", st.dir);
    int64_t n = p.n;
    for (int f = 0; f < 6; f++) {
        pg_image img;
        assert_int_equal(pg_image_read_exr(path, pg_cube_face_name(f), &img, &err), PG_OK);
        assert_int_equal(img.width, n);
        assert_int_equal(img.channels, 1);
        for (int64_t y = 0; y < n; y++) /* file rows top-down, face rows bottom-up */
            assert_memory_equal(img.data + (n - 1 - y) * n, p.height[f] + y * n,
                                (size_t)n * sizeof(float));
        pg_image_free(&img);
    }
    /* OpenEXR's own tool and OpenImageIO read it: six float parts named by face */
    char cmd[1500], out[65536];
    snprintf(cmd, sizeof cmd, "exrheader '%s' 2>&1", path);
    assert_int_equal(fixture_sh(cmd, out, sizeof out), 0);
    for (int f = 0; f < 6; f++) {
        char want[64];
        snprintf(want, sizeof want, "name (type string): \"%s\"", pg_cube_face_name(f));
        assert_non_null(strstr(out, want));
    }
    snprintf(cmd, sizeof cmd, "oiiotool --info -v '%s' 2>&1", path);
    assert_int_equal(fixture_sh(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "6 subimages"));
    assert_non_null(strstr(out, "float"));
    pg_planet_free(&p);
}

/* A grey planet (everything above the sea) with, optionally, a Gaussian hill of 8 km
 * and 0.05 rad at latitude 0, longitude 0: the centre of globe_lon000.png. */
static void hill_planet(pg_planet *p, bool hill) {
    pg_error err = {0};
    assert_int_equal(pg_planet_alloc(p, PG_CUBE_EQUIANGULAR, 1, 128, pg_ellipsoid_wgs84(), &err),
                     PG_OK);
    p->sea_level = -100;
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, p->projection, 1, 128, &err), PG_OK);
    for (int f = 0; f < 6; f++)
        for (int64_t i = 0; i < p->n * p->n; i++) {
            double d[3];
            pg_cube_texel_dir(&g, (int64_t)f * p->n * p->n + i, d);
            double ang = acos(d[0] > 1 ? 1 : d[0]) / 0.05;
            p->height[f][i] = hill ? (float)(8000 * exp(-ang * ang)) : 0;
            for (int c = 0; c < 3; c++)
                p->albedo[f][3 * i + c] = 0.5f;
        }
}

/* Pixel (x, y) of a planet's globe_lon000.png rendered at 256 px, grey 0..1. */
static void render_lon000(bool hill, const char *tag, pg_image *img) {
    pg_planet p;
    hill_planet(&p, hill);
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.glb = o.exr = false;
    o.globe_size = 256;
    char dir[1024], path[1200];
    pg_test_scratch_dir(tag, dir, sizeof dir);
    pg_planet_dir_paths st = {.dir = dir};
    pg_error err = {0};
    assert_int_equal(pg_export_write(&p, &o, pg_planet_dir_path, &st, NULL, &err), PG_OK);
    pg_planet_free(&p);
    snprintf(path, sizeof path, "%s/globe_lon000.png", dir);
    assert_int_equal(pg_image_read(path, 0, img, &err), PG_OK);
    assert_int_equal(img->width, 256);
}

static double grey_at(const pg_image *img, int x, int y) {
    return img->data[((size_t)y * img->width + x) * img->channels] * img->unit_scale;
}

/* The light comes from the upper left (north-west in globe_lon000, whose right is
 * east). So on the hill the north-west flank is brighter than the flat planet there,
 * the south-east flank darker, and the top, where the slope is 0, the same; far from
 * the hill nothing changes. A gradient with a wrong sign or axis fails. */
static void test_globe_shades_relief(void **s) {
    (void)s;
    pg_image flat, hill;
    render_lon000(false, "export_globe_flat", &flat);
    render_lon000(true, "export_globe_hill", &hill);
    const int c = 128, d = 4; /* the hill's flanks are steepest 4.4 px from its top */
    double nw[2] = {grey_at(&flat, c - d, c - d), grey_at(&hill, c - d, c - d)};
    double se[2] = {grey_at(&flat, c + d - 1, c + d - 1), grey_at(&hill, c + d - 1, c + d - 1)};
    double top[2] = {0.5 * (grey_at(&flat, c - 1, c - 1) + grey_at(&flat, c, c)),
                     0.5 * (grey_at(&hill, c - 1, c - 1) + grey_at(&hill, c, c))};
    double far[2] = {grey_at(&flat, c + 60, c - 40), grey_at(&hill, c + 60, c - 40)};
    printf("flat / hill: north-west %.3f / %.3f, south-east %.3f / %.3f, top %.3f / %.3f, far "
           "%.3f / %.3f\n",
           nw[0], nw[1], se[0], se[1], top[0], top[1], far[0], far[1]);
    assert_true(nw[1] > 1.1 * nw[0]);
    assert_true(se[1] < 0.9 * se[0]);
    assert_true(fabs(top[1] - top[0]) < 0.05 * top[0]);
    assert_true(fabs(far[1] - far[0]) <= 1.0 / 255);
    pg_image_free(&flat);
    pg_image_free(&hill);
}

static uint8_t *read_all(const char *path, size_t *n) {
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = malloc(*n);
    assert_int_equal(fread(b, 1, *n, f), *n);
    fclose(f);
    return b;
}

/* Where `needle` occurs in the file (-1: nowhere). */
static long find_bytes(const uint8_t *hay, size_t n, const uint8_t *needle, size_t m) {
    for (size_t i = 0; m <= n && i + m <= n; i++)
        if (hay[i] == needle[0] && !memcmp(hay + i, needle, m)) return (long)i;
    return -1;
}

/* Export dir's planet as planet.glb only, with the given albedo PNGs (or none). */
static void export_glb(const pg_planet *p, const pg_planet_encoded *png, bool jpeg,
                       const char *dir) {
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.exr = o.previews = false;
    o.albedo_png = png;
    if (jpeg) o.texture_format = PG_EXPORT_TEXTURE_JPEG;
    pg_planet_dir_paths st = {.dir = dir};
    pg_error err = {0};
    assert_int_equal(pg_export_write(p, &o, pg_planet_dir_path, &st, NULL, &err), PG_OK);
}

/* pg_planet_save_encoded keeps each albedo face's file bytes. planet.glb encodes the
 * same bytes itself; given other PNGs (a 4 x 4 image per face) it embeds those, in
 * face order; with JPEG textures it ignores them. */
static void test_glb_embeds_saved_albedo(void **s) {
    (void)s;
    pg_planet p;
    fixture_earth(&p, 1, 64);
    char dir[1024], path[1200];
    pg_test_scratch_dir("export_albedo_reuse", dir, sizeof dir);
    pg_planet_dir_paths st = {.dir = dir};
    pg_planet_encoded kept, marks;
    pg_error err = {0};
    assert_int_equal(pg_planet_save_encoded(&p, pg_planet_dir_path, &st, &kept, &err), PG_OK);
    memset(&marks, 0, sizeof marks);
    for (int f = 0; f < 6; f++) {
        char name[64];
        pg_planet_albedo_name(f, name, sizeof name);
        snprintf(path, sizeof path, "%s/%s", dir, name);
        size_t n;
        uint8_t *file = read_all(path, &n);
        assert_int_equal(n, kept.albedo_png_size[f]);
        assert_memory_equal(file, kept.albedo_png[f], n);
        free(file);
        pg_image tiny;
        assert_int_equal(pg_image_alloc(&tiny, 4, 4, 3, &err), PG_OK);
        for (int i = 0; i < 48; i++)
            tiny.data[i] = (float)((f * 48 + i) % 251) / 250.0f;
        assert_int_equal(
            pg_image_encode_png(&tiny, 8, &marks.albedo_png[f], &marks.albedo_png_size[f], &err),
            PG_OK);
        pg_image_free(&tiny);
    }
    snprintf(path, sizeof path, "%s/planet.glb", dir);
    size_t n;
    export_glb(&p, NULL, false, dir); /* encoded by the exporter */
    uint8_t *glb = read_all(path, &n);
    for (int f = 0; f < 6; f++)
        assert_true(find_bytes(glb, n, kept.albedo_png[f], kept.albedo_png_size[f]) > 0);
    free(glb);
    export_glb(&p, &marks, false, dir); /* given */
    glb = read_all(path, &n);
    long last = 0;
    for (int f = 0; f < 6; f++) {
        long at = find_bytes(glb, n, marks.albedo_png[f], marks.albedo_png_size[f]);
        assert_true(at > last);
        last = at;
        assert_int_equal(find_bytes(glb, n, kept.albedo_png[f], kept.albedo_png_size[f]), -1);
    }
    free(glb);
    export_glb(&p, &marks, true, dir); /* JPEG textures: the PNGs do not apply */
    glb = read_all(path, &n);
    for (int f = 0; f < 6; f++)
        assert_int_equal(find_bytes(glb, n, marks.albedo_png[f], marks.albedo_png_size[f]), -1);
    free(glb);
    pg_planet_encoded_free(&kept);
    pg_planet_encoded_free(&marks);
    for (int f = 0; f < 6; f++)
        assert_null(kept.albedo_png[f]);
    pg_planet_free(&p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_options_checked),
        cmocka_unit_test(test_mesh_watertight_and_displaced), cmocka_unit_test(test_exr_roundtrip),
        cmocka_unit_test(test_globe_shades_relief), cmocka_unit_test(test_glb_embeds_saved_albedo)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
