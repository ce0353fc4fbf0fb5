/* Shared by the material tests: an integration frame about a lobe axis A in which the
 * surface's horizon is handled exactly, and composite Gauss-Legendre cell integrals over
 * (u = cos angle to A, phi), the solid-angle measure being du dphi.
 * Frame: A, T, B with n = cos_t A + sin_t T (sin_t >= 0), so n.w > 0 <=> |phi| < phi_h(u). */
#ifndef VBL_TEST_MATERIAL_UTIL_H
#define VBL_TEST_MATERIAL_UTIL_H

#include <stdlib.h>

#include "material/material.h"

typedef struct mt_frame { vbl_vec3 a, t, b; double cos_t, sin_t; } mt_frame;

static inline mt_frame mt_frame_make(vbl_vec3 axis, vbl_vec3 n)
{
    mt_frame f;
    f.a = vbl_v3_normalize(axis);
    vbl_vec3 tn = vbl_v3_sub(n, vbl_v3_scale(f.a, vbl_v3_dot(n, f.a)));
    if (vbl_v3_length(tn) > 1e-12) {
        f.t = vbl_v3_normalize(tn);
        f.b = vbl_v3_cross(f.a, f.t);
    } else {
        vbl_v3_basis(f.a, &f.t, &f.b);
    }
    f.cos_t = vbl_v3_dot(n, f.a);
    f.sin_t = fmax(0.0, vbl_v3_dot(n, f.t));
    return f;
}

static inline vbl_vec3 mt_dir(const mt_frame* f, double u, double phi)
{
    double s = sqrt(fmax(0.0, 1.0 - u * u));
    return vbl_v3_add(vbl_v3_scale(f->a, u), vbl_v3_add(vbl_v3_scale(f->t, s * cos(phi)), vbl_v3_scale(f->b, s * sin(phi))));
}

static inline void mt_coords(const mt_frame* f, vbl_vec3 w, double* u, double* phi)
{
    *u = vbl_clamp(vbl_v3_dot(w, f->a), -1.0, 1.0);
    *phi = atan2(vbl_v3_dot(w, f->b), vbl_v3_dot(w, f->t)); /* (-pi, pi] */
}

/* Directions with n.w > 0 at this u: |phi| < phi_h. */
static inline double mt_phi_horizon(const mt_frame* f, double u)
{
    double s = sqrt(fmax(0.0, 1.0 - u * u)), den = s * f->sin_t, num = -u * f->cos_t;
    if (den <= 1e-300) return num < 0.0 ? VBL_PI : 0.0;
    double x = num / den;
    return x <= -1.0 ? VBL_PI : (x >= 1.0 ? 0.0 : acos(x));
}

static const double mt_gl_x[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                                  0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
static const double mt_gl_w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                                  0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

typedef vbl_vec3 (*mt_fn)(vbl_vec3 w, void* ctx);

/* Integral of fn over the cell [u0, u1] x [phi0, phi1] restricted to the upper hemisphere of n,
 * with su x sphi sub-intervals of 8-point Gauss-Legendre (u split at 0 where the cell crosses
 * it: lobes about A end at u = 0). */
static inline vbl_vec3 mt_cell_integral(const mt_frame* f, mt_fn fn, void* ctx, double u0, double u1, double phi0,
                                        double phi1, int su, int sphi)
{
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    /* break points: u = 0 and u = +-sin_t (the horizon's tangencies: square-root kinks) */
    const double breaks[3] = {0.0, f->sin_t, -f->sin_t};
    for (int k = 0; k < 3; ++k) {
        double ub = breaks[k];
        if (u0 < ub && ub < u1 && (ub - u0) > 1e-15 && (u1 - ub) > 1e-15) {
            acc = mt_cell_integral(f, fn, ctx, u0, ub, phi0, phi1, su, sphi);
            return vbl_v3_add(acc, mt_cell_integral(f, fn, ctx, ub, u1, phi0, phi1, su, sphi));
        }
    }
    if (u0 >= 0.0 && 1.0 - u1 < 0.4 * (1.0 - u0) && 1.0 - u0 > 1e-10) {
        /* graded towards u = 1, where the lobes peak: pieces with 1 - u halving */
        double um = 1.0 - 0.5 * (1.0 - u0);
        acc = mt_cell_integral(f, fn, ctx, u0, um, phi0, phi1, su, sphi);
        return vbl_v3_add(acc, mt_cell_integral(f, fn, ctx, um, u1, phi0, phi1, su, sphi));
    }
    double hu = (u1 - u0) / su;
    for (int i = 0; i < su; ++i) {
        for (int k = 0; k < 8; ++k) {
            double u = u0 + hu * (i + 0.5 + 0.5 * mt_gl_x[k]), wu = 0.5 * hu * mt_gl_w[k];
            double ph = mt_phi_horizon(f, u), lo = fmax(phi0, -ph), hi = fmin(phi1, ph);
            if (!(hi > lo)) continue;
            double hp = (hi - lo) / sphi;
            for (int j = 0; j < sphi; ++j) {
                for (int l = 0; l < 8; ++l) {
                    double phi = lo + hp * (j + 0.5 + 0.5 * mt_gl_x[l]), wp = 0.5 * hp * mt_gl_w[l];
                    acc = vbl_v3_add(acc, vbl_v3_scale(fn(mt_dir(f, u, phi), ctx), wu * wp));
                }
            }
        }
    }
    return acc;
}

/* Incoming-independent setup: a tilted normal and wo at polar angle theta_o (degrees) from it. */
static inline vbl_vec3 mt_normal(void) { return vbl_v3_normalize(vbl_v3(0.2, -0.3, 0.9)); }
static inline vbl_vec3 mt_wo(vbl_vec3 n, double theta_deg, double phi)
{
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    double th = theta_deg * VBL_PI / 180.0;
    return vbl_v3_normalize(vbl_v3_add(vbl_v3_scale(n, cos(th)),
                                       vbl_v3_add(vbl_v3_scale(t, sin(th) * cos(phi)), vbl_v3_scale(b, sin(th) * sin(phi)))));
}

static inline vbl_material mt_material(vbl_material_type type, double kd, double ks, double exponent, double rough)
{
    vbl_material m;
    m.type = type;
    m.albedo = vbl_v3(kd, kd, kd);
    m.specular = vbl_v3(ks, ks, ks);
    m.exponent = exponent;
    m.roughness = rough;
    return m;
}

typedef struct mt_ctx { const vbl_material* m; vbl_vec3 n, wo; double scale; } mt_ctx;

static inline vbl_vec3 mt_pdf_fn(vbl_vec3 w, void* ctx)
{
    const mt_ctx* c = (const mt_ctx*)ctx;
    return vbl_v3(c->scale * vbl_material_pdf(c->m, c->n, c->wo, w), 0.0, 0.0);
}

static inline vbl_vec3 mt_fcos_fn(vbl_vec3 w, void* ctx)
{
    const mt_ctx* c = (const mt_ctx*)ctx;
    return vbl_v3_scale(vbl_material_eval(c->m, c->n, c->wo, w), fmax(0.0, vbl_v3_dot(c->n, w)));
}

/* Integral of fn over the upper hemisphere in the frame about `axis`, u cells graded towards
 * u = 1 (1 - u = 2^-k down to 1e-12) for sharp lobes about the axis. */
static int mt_cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* Also split at u = +-sin_t, where the horizon becomes tangent to the circle u = const (the
 * inner integral has square-root kinks there), with cells graded towards those points. */
static inline vbl_vec3 mt_hemisphere_integral(const mt_frame* f, mt_fn fn, void* ctx)
{
    double edges[256];
    int ne = 0;
    edges[ne++] = -1.0;
    edges[ne++] = 0.0;
    edges[ne++] = 1.0;
    for (double d = 0.5; d > 1e-12; d *= 0.5) edges[ne++] = 1.0 - d;
    for (int s = -1; s <= 1; s += 2) {
        double k = s * f->sin_t;
        for (double d = 0.25; d > 1e-7; d *= 0.125) {
            if (k - d > -1.0) edges[ne++] = k - d;
            if (k + d < 1.0) edges[ne++] = k + d;
        }
        edges[ne++] = k;
    }
    qsort(edges, (size_t)ne, sizeof edges[0], mt_cmp_double);
    vbl_vec3 acc = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i + 1 < ne; ++i) {
        if (!(edges[i + 1] > edges[i])) continue;
        for (int j = 0; j < 16; ++j)
            acc = vbl_v3_add(acc, mt_cell_integral(f, fn, ctx, edges[i], edges[i + 1], -VBL_PI + j * VBL_PI / 8.0,
                                                   -VBL_PI + (j + 1) * VBL_PI / 8.0, 1, 2));
    }
    return acc;
}

/* The lobe axis used for binning: the mirror direction for glossy models, n otherwise. */
static inline vbl_vec3 mt_axis(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo)
{
    if (m->type == VBL_MATERIAL_LAMBERT) return n;
    return vbl_v3_normalize(vbl_v3_sub(vbl_v3_scale(n, 2.0 * vbl_v3_dot(n, wo)), wo));
}

#endif
