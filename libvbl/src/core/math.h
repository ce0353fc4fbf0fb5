/* Small double-precision vector math used everywhere in the core (header-only, inline). */
#ifndef VBL_CORE_MATH_H
#define VBL_CORE_MATH_H

#include <math.h>

#ifndef VBL_PI
#define VBL_PI 3.14159265358979323846
#endif
#define VBL_INV_PI (1.0 / VBL_PI)
#define VBL_INV_4PI (1.0 / (4.0 * VBL_PI))

typedef struct vbl_vec3 { double x, y, z; } vbl_vec3;

static inline vbl_vec3 vbl_v3(double x, double y, double z) { vbl_vec3 r = {x, y, z}; return r; }
static inline vbl_vec3 vbl_v3_add(vbl_vec3 a, vbl_vec3 b) { return vbl_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vbl_vec3 vbl_v3_sub(vbl_vec3 a, vbl_vec3 b) { return vbl_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vbl_vec3 vbl_v3_mul(vbl_vec3 a, vbl_vec3 b) { return vbl_v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vbl_vec3 vbl_v3_scale(vbl_vec3 a, double s) { return vbl_v3(a.x * s, a.y * s, a.z * s); }
static inline vbl_vec3 vbl_v3_madd(vbl_vec3 a, vbl_vec3 d, double t) { return vbl_v3(a.x + d.x * t, a.y + d.y * t, a.z + d.z * t); }
static inline double vbl_v3_dot(vbl_vec3 a, vbl_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vbl_vec3 vbl_v3_cross(vbl_vec3 a, vbl_vec3 b)
{
    return vbl_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double vbl_v3_length(vbl_vec3 a) { return sqrt(vbl_v3_dot(a, a)); }
/* Returns `a` normalized, or (0,0,1) for a zero-length vector (never NaN). */
static inline vbl_vec3 vbl_v3_normalize(vbl_vec3 a)
{
    double len = vbl_v3_length(a);
    return len > 0.0 ? vbl_v3_scale(a, 1.0 / len) : vbl_v3(0.0, 0.0, 1.0);
}
static inline double vbl_v3_max_component(vbl_vec3 a) { return fmax(a.x, fmax(a.y, a.z)); }
static inline double vbl_v3_get(vbl_vec3 a, int axis) { return axis == 0 ? a.x : (axis == 1 ? a.y : a.z); }

/* Orthonormal basis around unit n (Duff et al. 2017, branchless). */
static inline void vbl_v3_basis(vbl_vec3 n, vbl_vec3* t, vbl_vec3* b)
{
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double c = n.x * n.y * a;
    *t = vbl_v3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = vbl_v3(c, sign + n.y * n.y * a, -n.y);
}

static inline double vbl_clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* Row-major 3x4 affine map: p' = M[0..2][0..2] p + M[.][3]. */
typedef struct vbl_affine { double m[3][4]; } vbl_affine;

static inline vbl_vec3 vbl_affine_point(const vbl_affine* a, vbl_vec3 p)
{
    return vbl_v3(a->m[0][0] * p.x + a->m[0][1] * p.y + a->m[0][2] * p.z + a->m[0][3],
                  a->m[1][0] * p.x + a->m[1][1] * p.y + a->m[1][2] * p.z + a->m[1][3],
                  a->m[2][0] * p.x + a->m[2][1] * p.y + a->m[2][2] * p.z + a->m[2][3]);
}
static inline vbl_vec3 vbl_affine_vector(const vbl_affine* a, vbl_vec3 v)
{
    return vbl_v3(a->m[0][0] * v.x + a->m[0][1] * v.y + a->m[0][2] * v.z,
                  a->m[1][0] * v.x + a->m[1][1] * v.y + a->m[1][2] * v.z,
                  a->m[2][0] * v.x + a->m[2][1] * v.y + a->m[2][2] * v.z);
}

#endif
