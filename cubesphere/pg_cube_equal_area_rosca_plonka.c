/* pg_cube_equal_area_rosca_plonka.c - the equal-area cube-to-sphere map of
 * D. Rosca and G. Plonka, "Uniform spherical grids via equal area projection from
 * the cube to the sphere", J. Comput. Appl. Math. 236(6):1033-1041, 2011.
 *
 * The idea: split a face into the four triangles cut by its diagonals. In the
 * triangle |b| <= |a| (grid coordinates, half-width 1), the ray through (a, b) from
 * the face centre keeps its slope t = b/a, and is sent to the spherical azimuth Phi
 * that encloses the same share of area: the spherical wedge from azimuth 0 to Phi,
 * out to the face edge, has area Phi - asin(sin(Phi)/sqrt 2), and the square wedge
 * t' in [0, t] has area pi*t/12 in the same units (each face is 2*pi/3 of the unit
 * sphere). Writing c = pi*t/12 and Phi = c + psi, sin(c + psi) = sqrt2 * sin(psi)
 * gives psi = atan2(sin c, sqrt2 - cos c): closed form both ways. Along the ray,
 * area grows like a^2 on the square and like 1 - cos(theta) on the sphere, so
 * 1 - cos(theta) = a^2 * (1 - cos(theta_max(Phi))), where theta_max is the polar
 * angle of the face edge: cos(theta_max) = cos(Phi)/sqrt(1 + cos(Phi)^2). Both
 * factors have constant Jacobian, so the map is exactly equal-area; the inverse
 * undoes each closed-form step, hence round trips at round-off level. This is the
 * construction of Rosca & Plonka (their Lambert azimuthal step is folded into the
 * polar angle here). The map commutes with the face's 8 symmetries, so texel rows
 * still meet across seams. */
#include "pg_cube_internal.h"

#include "pg_vec3.h"

#include <math.h>

static const double PG_PI = 3.14159265358979323846;

/* The wedge |b| <= |a|, a != 0. */
static void wedge_forward(double a, double b, double *x, double *y, double *z) {
    double c = PG_PI * (b / a) / 12;
    double psi = atan2(sin(c), sqrt(2.0) - cos(c));
    double phi = c + psi;
    double cp = cos(phi);
    double h = a * a * (1 - cp / sqrt(1 + cp * cp)); /* 1 - cos(theta) */
    double st = sqrt(h * (2 - h));
    double s = a < 0 ? -st : st;
    *x = s * cp;
    *y = s * sin(phi);
    *z = 1 - h;
}

void pg_cube_rp_forward(double a, double b, double local[3]) {
    if (a == 0 && b == 0) {
        local[0] = local[1] = 0, local[2] = 1;
    } else if (fabs(b) <= fabs(a)) {
        wedge_forward(a, b, &local[0], &local[1], &local[2]);
    } else {
        wedge_forward(b, a, &local[1], &local[0], &local[2]);
    }
}

/* Inverse on the wedge |y| <= |x|, x != 0, for a unit vector. */
static void wedge_inverse(double x, double y, double z, double *a, double *b) {
    double phi = atan(y / x);
    double h = (x * x + y * y) / (1 + z); /* 1 - z without cancellation */
    double cp = cos(phi);
    double aa = sqrt(h / (1 - cp / sqrt(1 + cp * cp)));
    double c = phi - asin(sin(phi) / sqrt(2.0));
    *a = x < 0 ? -aa : aa;
    *b = (12 * c / PG_PI) * *a;
}

void pg_cube_rp_inverse(const double local[3], double *a, double *b) {
    double r = pg_vec3_length(local);
    double x = local[0] / r, y = local[1] / r, z = local[2] / r;
    if (x == 0 && y == 0) {
        *a = *b = 0;
    } else if (fabs(y) <= fabs(x)) {
        wedge_inverse(x, y, z, a, b);
    } else {
        wedge_inverse(y, x, z, b, a);
    }
}
