/* pg_gdal.c - the GDAL adapter behind pg_raster.h, on GDAL's C API (gdal.h,
 * cpl_conv.h, ogr_srs_api.h, gdal_utils.h); it belongs to the core module.
 *
 * Every entry point brackets its GDAL calls with gdal_begin/gdal_end: register the
 * drivers (idempotent), push a thread-local error handler whose user data is a struct
 * on our stack (so GDAL never prints, and there is no global state of ours), and turn
 * off GDAL's .aux.xml side files for this thread, so neither reading an input nor
 * writing an output leaves an extra file behind. The first GDAL error, flattened to
 * one line, becomes the pg_error message after the file name.
 *
 * Writing goes through an in-memory (MEM) dataset whose bands point at our buffer,
 * then GDALCreateCopy into the GTiff or COG driver: one path for both, and the only
 * way the COG driver writes. Creation options are validated against the driver first
 * (GDALValidateCreationOptions reports unknown keys and bad values as warnings,
 * which the handler turns into a refusal). */
#include "planetgen/pg_raster.h"

#include "pg_quantise.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- GDAL's messages, caught per call ---- */

typedef struct gdal_msgs {
    char error[256];   /* the first CE_Failure/CE_Fatal message */
    char warning[256]; /* the first CE_Warning message */
} gdal_msgs;

static void copy_line(char *dst, size_t size, const char *msg) {
    snprintf(dst, size, "%s", msg ? msg : "");
    for (char *p = dst; *p; p++)
        if (*p == '\n' || *p == '\r') *p = ' ';
}

static void CPL_STDCALL on_gdal_msg(CPLErr cls, CPLErrorNum no, const char *msg) {
    (void)no;
    gdal_msgs *m = CPLGetErrorHandlerUserData();
    if (!m) return;
    if (cls >= CE_Failure && !m->error[0]) copy_line(m->error, sizeof m->error, msg);
    if (cls == CE_Warning && !m->warning[0]) copy_line(m->warning, sizeof m->warning, msg);
}

static void gdal_begin(gdal_msgs *m) {
    memset(m, 0, sizeof *m);
    GDALAllRegister();
    CPLPushErrorHandlerEx(on_gdal_msg, m);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");
}

static void gdal_end(void) {
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", NULL);
    CPLPopErrorHandler();
}

static const char *why(const gdal_msgs *m, const char *fallback) {
    return m->error[0] ? m->error : fallback;
}

/* ---- georeferencing ---- */

void pg_georef_free(pg_georef *g) {
    if (!g) return;
    free(g->crs_wkt);
    memset(g, 0, sizeof *g);
}

pg_status pg_georef_copy(pg_georef *dst, const pg_georef *src, pg_error *err) {
    *dst = *src;
    dst->crs_wkt = NULL;
    if (src->crs_wkt && !(dst->crs_wkt = strdup(src->crs_wkt)))
        return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    return PG_OK;
}

bool pg_georef_present(const pg_georef *g) {
    return g && (g->has_transform || g->crs_wkt);
}

/* Fill kind, a, f, unit, name and the WKT from an SRS handle. */
static pg_status describe_srs(OGRSpatialReferenceH srs, pg_georef *g, pg_error *err) {
    const char *const fmt[] = {"FORMAT=WKT2_2019", NULL};
    char *wkt = NULL;
    if (OSRExportToWktEx(srs, &wkt, fmt) != OGRERR_NONE || !wkt) {
        CPLFree(wkt);
        return PG_OK; /* a CRS GDAL cannot describe counts as none */
    }
    g->crs_wkt = strdup(wkt);
    CPLFree(wkt);
    if (!g->crs_wkt) return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    const char *name = OSRGetName(srs);
    snprintf(g->crs_name, sizeof g->crs_name, "%s", name ? name : "unnamed");
    OGRErr e1 = OGRERR_NONE, e2 = OGRERR_NONE;
    double a = OSRGetSemiMajor(srs, &e1), invf = OSRGetInvFlattening(srs, &e2);
    if (e1 == OGRERR_NONE && e2 == OGRERR_NONE && a > 0) {
        g->a = a;
        g->f = invf > 0 ? 1 / invf : 0;
    }
    if (OSRIsGeographic(srs)) {
        g->kind = PG_CRS_GEOGRAPHIC;
        g->unit = OSRGetAngularUnits(srs, NULL) * 180 / 3.14159265358979323846;
    } else if (OSRIsProjected(srs)) {
        g->kind = PG_CRS_PROJECTED;
        g->unit = OSRGetLinearUnits(srs, NULL);
    } else {
        g->kind = PG_CRS_OTHER;
    }
    return PG_OK;
}

static pg_status read_georef(GDALDatasetH ds, pg_georef *g, pg_error *err) {
    memset(g, 0, sizeof *g);
    double t[6];
    if (GDALGetGeoTransform(ds, t) == CE_None) {
        const double id[6] = {0, 1, 0, 0, 0, 1};
        g->has_transform = memcmp(t, id, sizeof t) != 0;
        memcpy(g->transform, t, sizeof t);
    }
    CPLErrorReset(); /* "no geotransform" is not an error here */
    if (GDALGetRasterCount(ds) > 0) {
        int has = 0;
        double v = GDALGetRasterNoDataValue(GDALGetRasterBand(ds, 1), &has);
        g->has_nodata = has != 0;
        g->nodata = has ? v : 0;
    }
    OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
    return srs ? describe_srs(srs, g, err) : PG_OK;
}

/* ---- reading ---- */

static GDALDatasetH open_raster(const char *path, gdal_msgs *m, pg_error *err) {
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
    if (!ds)
        pg_error_set(err, PG_ERR_BADINPUT, "%s: not a raster GDAL can read (%s)", path,
                     why(m, "no driver recognises it"));
    else if (GDALGetRasterCount(ds) < 1) {
        GDALClose(ds);
        ds = NULL;
        pg_error_set(err, PG_ERR_BADINPUT, "%s: a dataset with no raster band", path);
    }
    return ds;
}

pg_status pg_raster_probe(const char *path, int *width, int *height, int *bands, char driver[32],
                          pg_georef *geo, pg_error *err) {
    gdal_msgs m;
    gdal_begin(&m);
    GDALDatasetH ds = open_raster(path, &m, err);
    pg_status st = ds ? PG_OK : PG_ERR_BADINPUT;
    if (ds) {
        *width = GDALGetRasterXSize(ds);
        *height = GDALGetRasterYSize(ds);
        *bands = GDALGetRasterCount(ds);
        if (driver) snprintf(driver, 32, "%s", GDALGetDriverShortName(GDALGetDatasetDriver(ds)));
        if (geo) st = read_georef(ds, geo, err);
        GDALClose(ds);
    }
    gdal_end();
    return st;
}

static bool sample_type(GDALDataType t, pg_image_sample_type *st, float *scale) {
    switch (t) {
    case GDT_Byte:
        *st = PG_SAMPLE_UINT8, *scale = 1.0f / 255.0f;
        return true;
    case GDT_UInt16:
        *st = PG_SAMPLE_UINT16, *scale = 1.0f / 65535.0f;
        return true;
    case GDT_Int16:
        *st = PG_SAMPLE_INT16, *scale = 1.0f / 32767.0f;
        return true;
    case GDT_UInt32:
        *st = PG_SAMPLE_UINT32, *scale = 1.0f / 4294967295.0f;
        return true;
    case GDT_Int32:
        *st = PG_SAMPLE_INT32, *scale = 1.0f / 2147483647.0f;
        return true;
    case GDT_Float32:
        *st = PG_SAMPLE_FLOAT, *scale = 1.0f;
        return true;
    case GDT_Float64:
        *st = PG_SAMPLE_DOUBLE, *scale = 1.0f;
        return true;
    default:
        return false;
    }
}

static pg_status read_pixels(GDALDatasetH ds, const char *path, uint64_t max_pixels, pg_image *out,
                             gdal_msgs *m, pg_error *err) {
    int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds), nb = GDALGetRasterCount(ds);
    if (max_pixels == 0) max_pixels = PG_IMAGE_DEFAULT_MAX_PIXELS;
    uint64_t npix = (uint64_t)w * (uint64_t)h;
    if (w <= 0 || h <= 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: empty raster %dx%d", path, w, h);
    if (npix > max_pixels)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: %dx%d is %.0f Mpx, above the limit of %.0f Mpx", path, w, h,
                            npix / 1e6, max_pixels / 1e6);
    GDALDataType t = GDALGetRasterDataType(GDALGetRasterBand(ds, 1));
    pg_image_sample_type stype;
    float scale;
    if (!sample_type(t, &stype, &scale))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: unsupported sample type %s", path,
                            GDALGetDataTypeName(t));
    size_t n = (size_t)npix * (size_t)nb;
    float *data = malloc(n * sizeof *data);
    if (!data)
        return pg_error_set(err, PG_ERR_NOMEM, "%s: cannot allocate %.0f MB for pixels", path,
                            n * 4.0 / 1e6);
    GSpacing px = (GSpacing)nb * 4;
    CPLErr e = GDALDatasetRasterIOEx(ds, GF_Read, 0, 0, w, h, data, w, h, GDT_Float32, nb, NULL, px,
                                     px * w, 4, NULL);
    if (e != CE_None) {
        free(data);
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: corrupt or truncated raster (%s)", path,
                            why(m, "read failed"));
    }
    memset(out, 0, sizeof *out);
    out->width = w, out->height = h, out->channels = nb, out->data = data;
    out->src_type = stype, out->unit_scale = scale;
    snprintf(out->format_name, sizeof out->format_name, "%s",
             GDALGetDriverShortName(GDALGetDatasetDriver(ds)));
    return PG_OK;
}

pg_status pg_raster_read(const char *path, uint64_t max_pixels, pg_image *out, pg_georef *geo,
                         pg_error *err) {
    memset(out, 0, sizeof *out);
    if (geo) memset(geo, 0, sizeof *geo);
    gdal_msgs m;
    gdal_begin(&m);
    GDALDatasetH ds = open_raster(path, &m, err);
    pg_status st = ds ? PG_OK : PG_ERR_BADINPUT;
    if (st == PG_OK && geo) st = read_georef(ds, geo, err);
    if (st == PG_OK) st = read_pixels(ds, path, max_pixels, out, &m, err);
    if (ds) GDALClose(ds);
    gdal_end();
    if (st != PG_OK) pg_georef_free(geo);
    return st;
}

/* ---- writing ---- */

static bool has_key(const pg_raster_write_opts *o, const char *key) {
    size_t n = strlen(key);
    for (int i = 0; o && i < o->noptions; i++)
        if (!strncasecmp(o->options[i], key, n) && o->options[i][n] == '=') return true;
    return false;
}

pg_status pg_raster_check_options(const pg_raster_write_opts *o, const char *option,
                                  pg_error *err) {
    if (!o || o->noptions == 0) return PG_OK;
    if (o->noptions > PG_RASTER_MAX_OPTIONS)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: more than %d creation options", option,
                            PG_RASTER_MAX_OPTIONS);
    for (int i = 0; i < o->noptions; i++) {
        const char *eq = strchr(o->options[i], '=');
        if (!eq || eq == o->options[i] || !eq[1])
            return pg_error_set(err, PG_ERR_BADINPUT, "%s '%s': expected KEY=VALUE", option,
                                o->options[i]);
    }
    gdal_msgs m;
    gdal_begin(&m);
    const char *drv_name = o->cog ? "COG" : "GTiff";
    GDALDriverH drv = GDALGetDriverByName(drv_name);
    pg_status st = PG_OK;
    if (!drv) {
        st = pg_error_set(err, PG_ERR_RUNTIME, "GDAL has no %s driver", drv_name);
    } else {
        char **list = NULL;
        for (int i = 0; i < o->noptions; i++)
            list = CSLAddString(list, o->options[i]);
        int ok = GDALValidateCreationOptions(drv, (CSLConstList)list);
        CSLDestroy(list);
        if (!ok || m.warning[0] || m.error[0])
            st = pg_error_set(err, PG_ERR_BADINPUT, "%s: %s", option,
                              m.warning[0] ? m.warning : why(&m, "rejected by GDAL"));
    }
    gdal_end();
    return st;
}

/* The creation options: the user's, or DEFLATE (with the predictor that suits the
 * sample type) when the user set no compression. */
static char **creation_list(const pg_raster_write_opts *o, pg_raster_type type) {
    char **list = NULL;
    for (int i = 0; o && i < o->noptions; i++)
        list = CSLAddString(list, o->options[i]);
    if (!has_key(o, "COMPRESS")) {
        list = CSLAddString(list, "COMPRESS=DEFLATE");
        if (!has_key(o, "PREDICTOR"))
            list = CSLAddString(list, type == PG_RASTER_FLOAT32 ? "PREDICTOR=3" : "PREDICTOR=2");
    }
    return list;
}

/* A MEM dataset whose bands read from `buf` (float32 or byte, interleaved). */
static GDALDatasetH mem_dataset(const void *buf, int w, int h, int ch, GDALDataType t) {
    GDALDriverH mem = GDALGetDriverByName("MEM");
    GDALDatasetH ds = mem ? GDALCreate(mem, "", w, h, 0, t, NULL) : NULL;
    int size = GDALGetDataTypeSizeBytes(t);
    for (int c = 0; ds && c < ch; c++) {
        char ptr[64], pix[64], line[64];
        snprintf(ptr, sizeof ptr, "DATAPOINTER=%p", (void *)((const char *)buf + (size_t)c * size));
        snprintf(pix, sizeof pix, "PIXELOFFSET=%d", ch * size);
        snprintf(line, sizeof line, "LINEOFFSET=%lld", (long long)w * ch * size);
        char *opts[] = {ptr, pix, line, NULL};
        if (GDALAddBand(ds, t, opts) != CE_None) {
            GDALClose(ds);
            return NULL;
        }
    }
    return ds;
}

static pg_status set_georef(GDALDatasetH ds, const pg_georef *geo, int ch, pg_error *err,
                            const char *path, gdal_msgs *m) {
    if (!geo) return PG_OK;
    double t[6];
    memcpy(t, geo->transform, sizeof t);
    if (geo->has_transform && GDALSetGeoTransform(ds, t) != CE_None)
        return pg_error_set(err, PG_ERR_RUNTIME, "%s: cannot set the geotransform (%s)", path,
                            why(m, "GDAL refused it"));
    if (geo->crs_wkt && GDALSetProjection(ds, geo->crs_wkt) != CE_None)
        return pg_error_set(err, PG_ERR_RUNTIME, "%s: cannot set the coordinate system (%s)", path,
                            why(m, "GDAL refused it"));
    for (int c = 0; geo->has_nodata && c < ch; c++)
        if (GDALSetRasterNoDataValue(GDALGetRasterBand(ds, c + 1), geo->nodata) != CE_None)
            return pg_error_set(err, PG_ERR_RUNTIME, "%s: cannot set NoData (%s)", path,
                                why(m, "GDAL refused it"));
    return PG_OK;
}

pg_status pg_raster_write_geotiff(const char *path, const pg_image *img, pg_raster_type type,
                                  const pg_georef *geo, const pg_raster_write_opts *o,
                                  pg_error *err) {
    const int w = img->width, h = img->height, ch = img->channels;
    if (ch != 1 && ch != 3)
        return pg_error_set(err, PG_ERR_RUNTIME, "%s: %d channels (1 or 3 only)", path, ch);
    size_t n = (size_t)w * h * ch;
    uint8_t *bytes = NULL;
    if (type == PG_RASTER_BYTE) {
        if (!(bytes = malloc(n))) return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", path);
        /* the rule of every image writer here (pg_quantise.h: lround(v 255) in double),
         * so a GeoTIFF equals the PNG of the same albedo byte for byte; rounding
         * v * 255 + 0.5 in float moved values near a half up by one */
        for (size_t i = 0; i < n; i++) {
            double v = (double)img->data[i];
            bytes[i] = (uint8_t)(v >= 1.0 ? 255 : v > 0 ? pg_round_half_up(v * 255.0) : 0);
        }
    }
    gdal_msgs m;
    gdal_begin(&m);
    GDALDataType t = type == PG_RASTER_BYTE ? GDT_Byte : GDT_Float32;
    GDALDatasetH src = mem_dataset(bytes ? (const void *)bytes : img->data, w, h, ch, t);
    pg_status st = src ? PG_OK
                       : pg_error_set(err, PG_ERR_RUNTIME, "%s: cannot stage the raster (%s)", path,
                                      why(&m, "no MEM driver"));
    if (st == PG_OK && ch == 3)
        for (int c = 0; c < 3; c++)
            GDALSetRasterColorInterpretation(GDALGetRasterBand(src, c + 1), GCI_RedBand + c);
    if (st == PG_OK) st = set_georef(src, geo, ch, err, path, &m);
    const char *drv_name = o && o->cog ? "COG" : "GTiff";
    GDALDriverH drv = GDALGetDriverByName(drv_name);
    if (st == PG_OK && !drv)
        st = pg_error_set(err, PG_ERR_RUNTIME, "GDAL has no %s driver", drv_name);
    if (st == PG_OK) {
        char **list = creation_list(o, type);
        if (ch == 3 && !(o && o->cog)) list = CSLAddString(list, "PHOTOMETRIC=RGB");
        GDALDatasetH dst = GDALCreateCopy(drv, path, src, TRUE, list, NULL, NULL);
        CSLDestroy(list);
        if (dst) GDALClose(dst); /* flushes: a failed write shows as an error message */
        if (!dst || m.error[0])
            st = pg_error_set(err, PG_ERR_IO, "%s: cannot write the GeoTIFF (%s)", path,
                              why(&m, "disk full?"));
    }
    if (src) GDALClose(src);
    gdal_end();
    free(bytes);
    return st;
}

pg_status pg_raster_geographic_crs(double a, double f, pg_georef *geo, pg_error *err) {
    gdal_msgs m;
    gdal_begin(&m);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    const double wgs_a = 6378137.0, wgs_f = 1 / 298.257223563;
    OGRErr e;
    if (fabs(a - wgs_a) < 1e-3 && fabs(f - wgs_f) < 1e-12) {
        e = OSRImportFromEPSG(srs, 4326);
    } else {
        char name[96];
        if (f > 0)
            snprintf(name, sizeof name, "planetgen planet (ellipsoid a = %.3f m, 1/f = %.9g)", a,
                     1 / f);
        else
            snprintf(name, sizeof name, "planetgen planet (sphere r = %.3f m)", a);
        e = OSRSetGeogCS(srs, name, "planetgen planet datum",
                         f > 0 ? "planetgen ellipsoid" : "planetgen sphere", a, f > 0 ? 1 / f : 0.0,
                         "Reference meridian", 0.0, SRS_UA_DEGREE, atof(SRS_UA_DEGREE_CONV));
    }
    pg_status st = PG_OK;
    memset(geo, 0, sizeof *geo);
    if (e != OGRERR_NONE)
        st = pg_error_set(err, PG_ERR_RUNTIME, "cannot make the planet's CRS (%s)",
                          why(&m, "OGR refused it"));
    else
        st = describe_srs(srs, geo, err);
    if (st == PG_OK && !geo->crs_wkt)
        st = pg_error_set(err, PG_ERR_RUNTIME, "cannot describe the planet's CRS as WKT");
    OSRDestroySpatialReference(srs);
    gdal_end();
    return st;
}

/* GDAL writes a source as relative to the VRT only when the source's name exists at
 * the time. The staged sources get their final names only when the command succeeds,
 * so the VRT is built in a private /vsimem/ directory where empty placeholders carry
 * the final names, then its bytes (GDAL's XML, untouched) are copied to path. */
static pg_status vsimem_touch(const char *name, pg_error *err) {
    VSILFILE *f = VSIFOpenL(name, "wb");
    if (!f) return pg_error_set(err, PG_ERR_NOMEM, "%s: cannot create in memory", name);
    VSIFCloseL(f);
    return PG_OK;
}

static pg_status copy_out(const char *mem, const char *path, gdal_msgs *m, pg_error *err) {
    vsi_l_offset len = 0;
    GByte *buf = VSIGetMemFileBuffer(mem, &len, FALSE);
    if (!buf)
        return pg_error_set(err, PG_ERR_IO, "%s: cannot write the VRT (%s)", path,
                            why(m, "GDALBuildVRT wrote nothing"));
    FILE *f = fopen(path, "wb");
    if (!f) return pg_error_set(err, PG_ERR_IO, "%s: cannot write", path);
    size_t w = fwrite(buf, 1, (size_t)len, f);
    if (fclose(f) != 0 || w != (size_t)len)
        return pg_error_set(err, PG_ERR_IO, "%s: write failed (disk full?)", path);
    return PG_OK;
}

pg_status pg_raster_build_vrt(const char *path, int n, const char *const *src,
                              const char *const *names, pg_error *err) {
    gdal_msgs m;
    gdal_begin(&m);
    char dir[96], full[4200], vrt_mem[128];
    snprintf(dir, sizeof dir, "/vsimem/planetgen_vrt_%p", (void *)&m); /* unique per call */
    snprintf(vrt_mem, sizeof vrt_mem, "%s/mosaic.vrt", dir);
    pg_status st = PG_OK;
    GDALDatasetH *ds = calloc((size_t)n, sizeof *ds);
    if (!ds) st = pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", path);
    for (int i = 0; st == PG_OK && i < n; i++) {
        ds[i] = GDALOpenEx(src[i], GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
        if (!ds[i]) {
            st = pg_error_set(err, PG_ERR_RUNTIME, "%s: cannot open (%s)", src[i],
                              why(&m, "GDAL failed"));
            break;
        }
        snprintf(full, sizeof full, "%s/%s", dir, names[i]);
        st = vsimem_touch(full, err);
        GDALSetDescription(ds[i], full); /* the VRT names the source by this */
    }
    if (st == PG_OK) {
        GDALBuildVRTOptions *vo = GDALBuildVRTOptionsNew(NULL, NULL);
        int usage = 0;
        GDALDatasetH vrt = vo ? GDALBuildVRT(vrt_mem, n, ds, NULL, vo, &usage) : NULL;
        if (vo) GDALBuildVRTOptionsFree(vo);
        if (vrt) GDALClose(vrt); /* writes the XML */
        if (!vrt || usage || m.error[0])
            st = pg_error_set(err, PG_ERR_IO, "%s: cannot write the VRT (%s)", path,
                              why(&m, "GDALBuildVRT failed"));
    }
    if (st == PG_OK) st = copy_out(vrt_mem, path, &m, err);
    for (int i = 0; ds && i < n; i++)
        if (ds[i]) GDALClose(ds[i]);
    free(ds);
    VSIRmdirRecursive(dir);
    gdal_end();
    return st;
}
