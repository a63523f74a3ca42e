/* pg_geodesy.cpp - the C adapter over GeographicLib declared in pg_geo.h.
 *
 * Thin by design: every conversion is one GeographicLib call (Geocentric for
 * geodetic <-> ECEF, Geodesic for azimuths, PolygonArea for areas), so the
 * geodesy is GeographicLib's, accurate to round-off on any ellipsoid. A direction
 * d is turned into a surface point by scaling it onto the ellipsoid
 * (x^2 + y^2)/a^2 + z^2/b^2 = 1, then handed to Geocentric::Reverse, which returns
 * the geodetic latitude. C++ types never leave this file. */
#include "planetgen/pg_geo.h"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

using GeographicLib::Geocentric;
using GeographicLib::Geodesic;
using GeographicLib::PolygonArea;

extern "C" {

pg_ellipsoid pg_ellipsoid_sphere(void) {
    return pg_ellipsoid{PG_ELLIPSOID_SPHERE_RADIUS_M, 0.0};
}

pg_ellipsoid pg_ellipsoid_wgs84(void) {
    return pg_ellipsoid{GeographicLib::Constants::WGS84_a(), GeographicLib::Constants::WGS84_f()};
}

pg_status pg_ellipsoid_make(double a, double f, const char *option, pg_ellipsoid *out,
                            pg_error *err) {
    if (!std::isfinite(a) || a <= 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: radius must be > 0, got %g", option, a);
    if (!std::isfinite(f) || f < 0 || f >= 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: flattening must be in [0, 1), got %g",
                            option, f);
    *out = pg_ellipsoid{a, f};
    return PG_OK;
}

pg_status pg_ellipsoid_parse(const char *spec, const char *option, pg_ellipsoid *out,
                             pg_error *err) {
    if (!spec || !*spec) return pg_error_set(err, PG_ERR_BADINPUT, "%s: empty planet", option);
    if (!std::strcmp(spec, "sphere")) {
        *out = pg_ellipsoid_sphere();
        return PG_OK;
    }
    if (!std::strcmp(spec, "wgs84")) {
        *out = pg_ellipsoid_wgs84();
        return PG_OK;
    }
    char *end = nullptr;
    double a = std::strtod(spec, &end);
    if (end == spec || *end != ',')
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: expected sphere, wgs84 or RADIUS,FLATTENING, got '%s'", option,
                            spec);
    const char *fs = end + 1;
    double f = std::strtod(fs, &end);
    if (end == fs || *end != '\0')
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: expected sphere, wgs84 or RADIUS,FLATTENING, got '%s'", option,
                            spec);
    return pg_ellipsoid_make(a, f, option, out, err);
}

/* Scale a direction onto the ellipsoid surface. */
static void surface_point(const pg_ellipsoid *e, const double d[3], double p[3]) {
    double b = e->a * (1 - e->f);
    double q = (d[0] * d[0] + d[1] * d[1]) / (e->a * e->a) + d[2] * d[2] / (b * b);
    double s = 1 / std::sqrt(q);
    p[0] = d[0] * s, p[1] = d[1] * s, p[2] = d[2] * s;
}

void pg_geo_dirs_to_latlon(const pg_ellipsoid *e, size_t n, const double *dirs, double *lat,
                           double *lon) {
    Geocentric g(e->a, e->f);
    for (size_t i = 0; i < n; i++) {
        double p[3], h = 0;
        surface_point(e, dirs + 3 * i, p);
        g.Reverse(p[0], p[1], p[2], lat[i], lon[i], h);
    }
}

void pg_geo_dir_to_latlon(const pg_ellipsoid *e, const double dir[3], double *lat, double *lon) {
    pg_geo_dirs_to_latlon(e, 1, dir, lat, lon);
}

void pg_geo_latlons_to_dirs(const pg_ellipsoid *e, size_t n, const double *lat, const double *lon,
                            double *dirs) {
    Geocentric g(e->a, e->f);
    for (size_t i = 0; i < n; i++) {
        double x = 0, y = 0, z = 0;
        g.Forward(lat[i], lon[i], 0, x, y, z);
        double r = std::sqrt(x * x + y * y + z * z);
        dirs[3 * i] = x / r, dirs[3 * i + 1] = y / r, dirs[3 * i + 2] = z / r;
    }
}

void pg_geo_latlon_to_dir(const pg_ellipsoid *e, double lat, double lon, double dir[3]) {
    pg_geo_latlons_to_dirs(e, 1, &lat, &lon, dir);
}

void pg_geo_ecef(const pg_ellipsoid *e, double lat, double lon, double h, double xyz[3]) {
    Geocentric(e->a, e->f).Forward(lat, lon, h, xyz[0], xyz[1], xyz[2]);
}

void pg_geo_dir_to_ecef(const pg_ellipsoid *e, const double dir[3], double h, double xyz[3]) {
    Geocentric g(e->a, e->f);
    double p[3], lat = 0, lon = 0, h0 = 0;
    surface_point(e, dir, p);
    if (h == 0) {
        xyz[0] = p[0], xyz[1] = p[1], xyz[2] = p[2];
        return;
    }
    g.Reverse(p[0], p[1], p[2], lat, lon, h0);
    g.Forward(lat, lon, h, xyz[0], xyz[1], xyz[2]);
}

/* Interior angles from the azimuths of the edges: edge i -> i+1 leaves vertex i at
 * azi1 and arrives at vertex i+1 heading azi2, so the way back leaves at azi2+180. */
static void polygon_angles(const Geodesic &g, int n, const double *lat, const double *lon,
                           double *angles) {
    std::vector<double> out(n), back(n);
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        double azi1 = 0, azi2 = 0;
        g.Inverse(lat[i], lon[i], lat[j], lon[j], azi1, azi2);
        out[i] = azi1;
        back[j] = azi2 + 180;
    }
    for (int i = 0; i < n; i++) {
        double a = std::fmod(out[i] - back[i], 360.0);
        angles[i] = a < 0 ? a + 360 : a;
    }
}

void pg_geo_polygons(const pg_ellipsoid *e, size_t npoly, int nvert, const double *lat,
                     const double *lon, double *area, double *angles) {
    Geodesic g(e->a, e->f);
    PolygonArea poly(g);
    for (size_t k = 0; k < npoly; k++) {
        const double *la = lat + k * nvert, *lo = lon + k * nvert;
        poly.Clear();
        for (int i = 0; i < nvert; i++)
            poly.AddPoint(la[i], lo[i]);
        double perim = 0, a = 0;
        poly.Compute(false, true, perim, a);
        area[k] = std::fabs(a);
        if (angles) polygon_angles(g, nvert, la, lo, angles + k * nvert);
    }
}

double pg_geo_polygon_area(const pg_ellipsoid *e, int n, const double *lat, const double *lon,
                           double *angles) {
    double a;
    pg_geo_polygons(e, 1, n, lat, lon, &a, angles);
    return a;
}

double pg_geo_total_area(const pg_ellipsoid *e) {
    return Geodesic(e->a, e->f).EllipsoidArea();
}

/* The area between two parallels is that of the authalic sphere between their
 * authalic latitudes xi: A / (4 pi) * dlon * (sin xi1 - sin xi0), A the ellipsoid's
 * area. Exact on the ellipsoid (GeographicLib's authalic latitude, to round-off). */
void pg_geo_latlon_band_areas(const pg_ellipsoid *e, size_t n, const double *lat, double dlon,
                              double *area) {
    GeographicLib::Ellipsoid ell(e->a, e->f);
    const double deg = GeographicLib::Math::degree();
    const double k = ell.Area() / (4 * GeographicLib::Math::pi()) * std::fabs(dlon) * deg;
    double s0 = 0;
    for (size_t i = 0; i <= n; i++) {
        double phi = std::fmax(-90.0, std::fmin(90.0, lat[i]));
        double s1 = std::sin(ell.AuthalicLatitude(phi) * deg);
        if (i > 0) area[i - 1] = k * std::fabs(s1 - s0);
        s0 = s1;
    }
}

} /* extern "C" */
