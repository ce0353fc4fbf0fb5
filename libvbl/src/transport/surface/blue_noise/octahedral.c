/* Octahedral map and its exact cell solid angles (octahedral.h). */
#include "transport/surface/blue_noise/octahedral.h"

#include <stdlib.h>

#include "core/error.h"

static inline double sign1(double x) { return x >= 0.0 ? 1.0 : -1.0; }

void vbl_oct_encode(vbl_vec3 d, double* u, double* v)
{
    double s = fabs(d.x) + fabs(d.y) + fabs(d.z);
    double x = s > 0.0 ? d.x / s : 0.0, y = s > 0.0 ? d.y / s : 0.0, z = s > 0.0 ? d.z / s : 1.0;
    if (z < 0.0) {
        double fx = (1.0 - fabs(y)) * sign1(x), fy = (1.0 - fabs(x)) * sign1(y);
        x = fx;
        y = fy;
    }
    *u = vbl_clamp(0.5 * (x + 1.0), 0.0, 1.0);
    *v = vbl_clamp(0.5 * (y + 1.0), 0.0, 1.0);
}

/* Point on the octahedron for (x, y) in [-1, 1]^2 (piecewise linear). */
static vbl_vec3 oct_point(double x, double y)
{
    double z = 1.0 - fabs(x) - fabs(y);
    if (z < 0.0) {
        double fx = (1.0 - fabs(y)) * sign1(x), fy = (1.0 - fabs(x)) * sign1(y);
        x = fx;
        y = fy;
    }
    return vbl_v3(x, y, z);
}

vbl_vec3 vbl_oct_decode(double u, double v) { return vbl_v3_normalize(oct_point(2.0 * u - 1.0, 2.0 * v - 1.0)); }

int vbl_oct_cell(vbl_vec3 d, int res)
{
    double u, v;
    vbl_oct_encode(d, &u, &v);
    int cu = (int)(u * res), cv = (int)(v * res);
    cu = cu < 0 ? 0 : (cu >= res ? res - 1 : cu);
    cv = cv < 0 ? 0 : (cv >= res ? res - 1 : cv);
    return cv * res + cu;
}

vbl_vec3 vbl_oct_cell_center(int cell, int res)
{
    int cu = cell % res, cv = cell / res;
    return vbl_oct_decode((cu + 0.5) / res, (cv + 0.5) / res);
}

/* Solid angle of the spherical triangle of unit a, b, c (Van Oosterom and Strackee 1983). */
static double spherical_triangle(vbl_vec3 a, vbl_vec3 b, vbl_vec3 c)
{
    double num = fabs(vbl_v3_dot(a, vbl_v3_cross(b, c)));
    double den = 1.0 + vbl_v3_dot(a, b) + vbl_v3_dot(b, c) + vbl_v3_dot(c, a);
    double e = 2.0 * atan2(num, den);
    return e < 0.0 ? e + 2.0 * VBL_PI : e;
}

#define OCT_SUB 4 /* sub-squares per cell edge (only for the representative directions) */

vbl_result vbl_oct_table_init(vbl_oct_table* t, int res)
{
    t->resolution = 0;
    t->solid_angle = t->upper = NULL;
    t->direction = NULL;
    if (res < 2 || res > VBL_BN_OCT_RESOLUTION_MAX || res % 2 != 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "octahedral map: res = %d must be even in [2, %d]", res,
                         VBL_BN_OCT_RESOLUTION_MAX);
    size_t cells = (size_t)res * (size_t)res;
    t->solid_angle = (double*)calloc(cells, sizeof(double));
    t->upper = (double*)calloc(cells, sizeof(double));
    t->direction = (vbl_vec3*)calloc(cells, sizeof(vbl_vec3));
    if (!t->solid_angle || !t->upper || !t->direction) {
        vbl_oct_table_free(t);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "octahedral map: cannot allocate %zu cells", cells);
    }
    t->resolution = res;
    /* Sub-grid step h = 2 / (res * OCT_SUB) in [-1, 1]^2: the fold lines x = 0, y = 0 and
     * |x| + |y| = 1 run along grid lines and sub-square diagonals (res * OCT_SUB is even), so
     * each triangle below lies on one octahedron face and projects to a spherical triangle. */
    const int n = res * OCT_SUB;
    const double h = 2.0 / n;
    for (int cv = 0; cv < res; ++cv)
        for (int cu = 0; cu < res; ++cu) {
            int cell = cv * res + cu;
            vbl_vec3 sum_all = vbl_v3(0, 0, 0), sum_up = vbl_v3(0, 0, 0);
            double total = 0.0, up = 0.0;
            for (int sv = 0; sv < OCT_SUB; ++sv)
                for (int su = 0; su < OCT_SUB; ++su) {
                    int i = cu * OCT_SUB + su, j = cv * OCT_SUB + sv;
                    double x0 = -1.0 + i * h, x1 = -1.0 + (i + 1) * h, y0 = -1.0 + j * h, y1 = -1.0 + (j + 1) * h;
                    double xc = 0.5 * (x0 + x1), yc = 0.5 * (y0 + y1);
                    vbl_vec3 p00 = vbl_v3_normalize(oct_point(x0, y0)), p10 = vbl_v3_normalize(oct_point(x1, y0));
                    vbl_vec3 p01 = vbl_v3_normalize(oct_point(x0, y1)), p11 = vbl_v3_normalize(oct_point(x1, y1));
                    vbl_vec3 tri[2][3];
                    if (xc * yc > 0.0) { /* fold diagonal of slope -1 */
                        vbl_vec3 a[3] = {p00, p10, p01}, b[3] = {p10, p11, p01};
                        for (int k = 0; k < 3; ++k) tri[0][k] = a[k], tri[1][k] = b[k];
                    } else { /* slope +1 */
                        vbl_vec3 a[3] = {p00, p10, p11}, b[3] = {p00, p11, p01};
                        for (int k = 0; k < 3; ++k) tri[0][k] = a[k], tri[1][k] = b[k];
                    }
                    for (int k = 0; k < 2; ++k) {
                        double area = spherical_triangle(tri[k][0], tri[k][1], tri[k][2]);
                        vbl_vec3 centre = vbl_v3_add(vbl_v3_add(tri[k][0], tri[k][1]), tri[k][2]);
                        centre = vbl_v3_normalize(centre);
                        total += area;
                        sum_all = vbl_v3_madd(sum_all, centre, area);
                        if (centre.z > 0.0) {
                            up += area;
                            sum_up = vbl_v3_madd(sum_up, centre, area);
                        }
                    }
                }
            t->solid_angle[cell] = total;
            t->upper[cell] = up;
            t->direction[cell] = vbl_v3_normalize(up > 0.0 ? sum_up : sum_all);
        }
    return VBL_SUCCESS;
}

void vbl_oct_table_free(vbl_oct_table* t)
{
    free(t->solid_angle);
    free(t->upper);
    free(t->direction);
    t->solid_angle = t->upper = NULL;
    t->direction = NULL;
    t->resolution = 0;
}
