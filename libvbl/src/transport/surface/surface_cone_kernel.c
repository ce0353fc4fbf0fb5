/* VSL gather kernel over the cone (VBL eq 9; surface VSLs, VBL section 3.4). */
#include "transport/surface/surface_cone_kernel.h"

#include <stddef.h>

#include "sampling/phase_hg.h"

vbl_surface_lobe vbl_surface_lobe_phase(double g, vbl_vec3 m)
{
    vbl_surface_lobe l = {VBL_SURFACE_LOBE_PHASE, g, m, NULL, vbl_v3(0, 0, 1), vbl_v3(0, 0, 1)};
    return l;
}

vbl_surface_lobe vbl_surface_lobe_receiver(const vbl_material* material, vbl_vec3 n, vbl_vec3 wo)
{
    vbl_surface_lobe l = {VBL_SURFACE_LOBE_RECEIVER, 0.0, vbl_v3(0, 0, 1), material, n, wo};
    return l;
}

vbl_surface_lobe vbl_surface_lobe_sender(const vbl_material* material, vbl_vec3 n, vbl_vec3 wi)
{
    vbl_surface_lobe l = {VBL_SURFACE_LOBE_SENDER, 0.0, vbl_v3(0, 0, 1), material, n, wi};
    return l;
}

static double mean3(vbl_vec3 v) { return (v.x + v.y + v.z) * (1.0 / 3.0); }

vbl_vec3 vbl_surface_lobe_eval(const vbl_surface_lobe* l, vbl_vec3 omega)
{
    switch (l->kind) {
    case VBL_SURFACE_LOBE_PHASE: {
        double f = vbl_hg_eval(l->g, vbl_v3_dot(l->m, omega));
        return vbl_v3(f, f, f);
    }
    case VBL_SURFACE_LOBE_RECEIVER: {
        vbl_vec3 wi = vbl_v3_scale(omega, -1.0);
        double c = vbl_v3_dot(l->n, wi);
        if (!(c > 0.0)) return vbl_v3(0, 0, 0);
        return vbl_v3_scale(vbl_material_eval(l->material, l->n, l->w, wi), c);
    }
    case VBL_SURFACE_LOBE_SENDER:
    default: {
        double c = vbl_v3_dot(l->n, omega);
        if (!(c > 0.0)) return vbl_v3(0, 0, 0);
        return vbl_v3_scale(vbl_material_eval(l->material, l->n, omega, l->w), c);
    }
    }
}

double vbl_surface_lobe_max_in_cone(const vbl_surface_lobe* l, const vbl_vsl_cone* cone)
{
    if (!(cone->solid_angle > 0.0)) return mean3(vbl_surface_lobe_eval(l, cone->axis));
    switch (l->kind) {
    case VBL_SURFACE_LOBE_PHASE:
        return vbl_vsl_cone_hg_max(cone, l->g, l->m, NULL);
    case VBL_SURFACE_LOBE_RECEIVER: /* the cone of wi = -omega */
        return mean3(vbl_material_max_in_cone(l->material, l->n, l->w, vbl_v3_scale(cone->axis, -1.0),
                                              cone->cos_half));
    case VBL_SURFACE_LOBE_SENDER:
    default: {
        /* f(omega, w) cos(n, omega): the materials are reciprocal (material.h), so this is the
         * receiver form with wo = w over the cone of omega. */
        return mean3(vbl_material_max_in_cone(l->material, l->n, l->w, cone->axis, cone->cos_half));
    }
    }
}

double vbl_surface_lobe_pdf(const vbl_surface_lobe* l, vbl_vec3 omega)
{
    switch (l->kind) {
    case VBL_SURFACE_LOBE_PHASE:
        return vbl_hg_pdf(l->g, vbl_v3_dot(l->m, omega));
    case VBL_SURFACE_LOBE_RECEIVER:
        return vbl_material_pdf(l->material, l->n, l->w, vbl_v3_scale(omega, -1.0));
    case VBL_SURFACE_LOBE_SENDER:
    default:
        return vbl_material_pdf(l->material, l->n, l->w, omega);
    }
}

int vbl_surface_lobe_sample(const vbl_surface_lobe* l, double u0, double u1, double u2, vbl_vec3* omega,
                            double* pdf)
{
    if (l->kind == VBL_SURFACE_LOBE_PHASE) {
        *omega = vbl_hg_sample(l->g, l->m, u1, u2, pdf);
        return *pdf > 0.0;
    }
    vbl_vec3 dir, f;
    if (!vbl_material_sample(l->material, l->n, l->w, u0, u1, u2, &dir, pdf, &f)) return 0;
    *omega = l->kind == VBL_SURFACE_LOBE_RECEIVER ? vbl_v3_scale(dir, -1.0) : dir;
    return *pdf > 0.0;
}

static double fract(double x) { return x - floor(x); }

/* Lobe sampling is worth it: not a (near-)isotropic phase, and a lobe sample can land in the cone. */
static int lobe_used(const vbl_surface_lobe* l, const vbl_vsl_cone* cone)
{
    if (l->kind == VBL_SURFACE_LOBE_PHASE && fabs(l->g) < 0.2) return 0;
    return cone->solid_angle * vbl_surface_lobe_max_in_cone(l, cone) >= 0.01;
}

vbl_vec3 vbl_surface_cone_kernel(const vbl_surface_lobe* a, const vbl_surface_lobe* b, vbl_vec3 x, vbl_vec3 c,
                                 double radius, int n, const double jitter[3])
{
    vbl_vec3 zero = vbl_v3(0, 0, 0);
    vbl_vsl_cone cone;
    /* fallback axis at w == 0: a receiver's normal points towards where light comes from */
    vbl_vec3 fallback = a->kind == VBL_SURFACE_LOBE_PHASE ? a->m : vbl_v3_scale(a->n, -1.0);
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(x, c), radius, fallback)) return zero;
    if (!(cone.solid_angle > 0.0)) /* R == 0: A B / w^2 */
        return vbl_v3_scale(vbl_v3_mul(vbl_surface_lobe_eval(a, cone.axis), vbl_surface_lobe_eval(b, cone.axis)),
                            cone.geometry);
    if (n < 1) n = 1;
    const vbl_surface_lobe* lobes[2] = {a, b};
    int used[2] = {lobe_used(a, &cone), lobe_used(b, &cone)};
    const double golden = 0.61803398874989484820, plastic = 0.75487766624669276005;
    double j0 = fract(jitter[0]), j1 = fract(jitter[1]), j2 = fract(jitter[2]);
    vbl_vec3 sum = zero;
    for (int s = 0; s < 3; ++s) {
        if (s > 0 && !used[s - 1]) continue;
        for (int i = 0; i < n; ++i) {
            double u1 = fract((i + j0) / n), u2 = fract(i * golden + j1), u0 = fract(i * plastic + j2);
            vbl_vec3 w;
            if (s == 0) {
                w = vbl_vsl_cone_sample(&cone, u1, u2, NULL);
            } else {
                double p;
                if (!vbl_surface_lobe_sample(lobes[s - 1], u0, u1, u2, &w, &p)) continue;
                if (!vbl_vsl_cone_contains(&cone, w)) continue;
            }
            vbl_vec3 f = vbl_v3_mul(vbl_surface_lobe_eval(a, w), vbl_surface_lobe_eval(b, w));
            if (f.x == 0.0 && f.y == 0.0 && f.z == 0.0) continue;
            /* Balance heuristic relative to the cone pdf 1/Omega (no 1/Omega in thin cones):
             * f / (n sum_s p_s) = f Omega / (n (1 + Omega sum_lobes p)). */
            double extra = 0.0;
            for (int k = 0; k < 2; ++k)
                if (used[k]) extra += vbl_surface_lobe_pdf(lobes[k], w);
            sum = vbl_v3_add(sum, vbl_v3_scale(f, 1.0 / (1.0 + cone.solid_angle * extra)));
        }
    }
    /* (1 / (pi R^2)) Omega (sum / n) = geometry sum / n */
    return vbl_v3_scale(sum, cone.geometry / n);
}
