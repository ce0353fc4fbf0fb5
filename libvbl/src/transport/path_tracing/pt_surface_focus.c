/* pt.surface_focus: surface vertices' directions from BRDF sampling mixed with focus cones about
 * point lights in media (pt_surface_focus.h). */
#include "transport/path_tracing/pt_surface_focus.h"

#include <math.h>

#include "sampling/focus_cone.h"
#include "scene/scene.h"

void vbl_pt_surface_focus_init(const vbl_render_context* ctx, vbl_pt_surface_focus* sf)
{
    sf->fraction = 0.0;
    sf->count = 0;
    const vbl_scene* scene = ctx->scene;
    const double c = ctx->options.pt.surface_focus;
    vbl_vec3 lo, hi;
    if (!(c > 0.0) || !scene->surfaces || !vbl_scene_media_box(scene, &lo, &hi)) return;
    for (int i = 0; i < scene->light_count && sf->count < VBL_PT_SURFACE_FOCUS_MAX; ++i) {
        const vbl_light* l = &scene->lights[i];
        if (l->type != VBL_LIGHT_POINT && l->type != VBL_LIGHT_SPOT) continue;
        const vbl_vec3 p = l->position;
        if (p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z)
            sf->light[sf->count++] = p;
    }
    sf->radius = 0.5 * vbl_v3_length(vbl_v3_sub(hi, lo));
    if (sf->count > 0 && sf->radius > 0.0 && isfinite(sf->radius)) sf->fraction = c;
}

/* The axis and half-angle of light i's cone at the hit; 0 where the light is not above the
 * surface (the focus then takes no part at this vertex). */
static int vbl_pt_focus_cone(const vbl_pt_surface_focus* sf, int i, const vbl_surface_hit* hit, vbl_vec3* axis,
                             double* psi_max)
{
    const vbl_vec3 d = vbl_v3_sub(sf->light[i], hit->position);
    const double r = vbl_v3_length(d);
    if (!(r > 0.0) || !isfinite(r)) return 0;
    *axis = vbl_v3_scale(d, 1.0 / r);
    if (!(vbl_v3_dot(*axis, hit->geometric_normal) > 0.0)) return 0;
    *psi_max = atan2(sf->radius, r); /* in (0, pi/2] */
    return *psi_max > 0.0;
}

/* (1 / N) sum_i p_i(wi) over the lights above the surface, and N */
static double vbl_pt_focus_pdf(const vbl_pt_surface_focus* sf, const vbl_surface_hit* hit, vbl_vec3 wi, int* n_active)
{
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < sf->count; ++i) {
        vbl_vec3 axis;
        double psi_max;
        if (!vbl_pt_focus_cone(sf, i, hit, &axis, &psi_max)) continue;
        sum += vbl_focus_cone_pdf(axis, psi_max, wi);
        ++n;
    }
    *n_active = n;
    return n > 0 ? sum / n : 0.0;
}

double vbl_pt_surface_focus_pdf(const vbl_pt_surface_focus* sf, const vbl_material* m, const vbl_surface_hit* hit,
                                vbl_vec3 wo, vbl_vec3 wi)
{
    const double p = vbl_material_pdf(m, hit->shading_normal, wo, wi);
    if (!(sf->fraction > 0.0)) return p;
    int n;
    const double pf = vbl_pt_focus_pdf(sf, hit, wi, &n);
    return n > 0 ? sf->fraction * pf + (1.0 - sf->fraction) * p : p;
}

double vbl_pt_surface_focus_pdf_fn(const void* data, const vbl_material* m, const vbl_surface_hit* hit, vbl_vec3 wo,
                                   vbl_vec3 wi)
{
    return vbl_pt_surface_focus_pdf(data, m, hit, wo, wi);
}

int vbl_pt_surface_focus_sample(const vbl_pt_surface_focus* sf, const vbl_material* m, const vbl_surface_hit* hit,
                                vbl_vec3 wo, double u0, double u1, double u2, vbl_vec3* wi, double* pdf,
                                vbl_vec3* f)
{
    const double c = sf->fraction;
    int n = 0;
    vbl_vec3 axes[VBL_PT_SURFACE_FOCUS_MAX];
    double psi[VBL_PT_SURFACE_FOCUS_MAX];
    for (int i = 0; c > 0.0 && i < sf->count; ++i)
        if (vbl_pt_focus_cone(sf, i, hit, &axes[n], &psi[n])) ++n;
    if (n == 0) return vbl_material_sample(m, hit->shading_normal, wo, u0, u1, u2, wi, pdf, f);
    double p_brdf, p_focus = 0.0;
    if (u0 < c) { /* a focus cone: light k = floor(n u0 / c) */
        int k = (int)(u0 / c * n);
        if (k >= n) k = n - 1;
        double pk;
        if (!vbl_focus_cone_sample(axes[k], psi[k], u1, u2, wi, &pk)) return 0;
        *f = vbl_material_eval(m, hit->shading_normal, wo, *wi);
        p_brdf = vbl_material_pdf(m, hit->shading_normal, wo, *wi);
    } else { /* the BRDF, with (u0 - c) / (1 - c) uniform in [0, 1) again */
        double v = (u0 - c) / (1.0 - c);
        if (!(v < 1.0)) v = nextafter(1.0, 0.0);
        if (!vbl_material_sample(m, hit->shading_normal, wo, v, u1, u2, wi, &p_brdf, f)) return 0;
    }
    /* the mixture's density from the densities' own formulas (the same function as _pdf) */
    for (int j = 0; j < n; ++j) p_focus += vbl_focus_cone_pdf(axes[j], psi[j], *wi);
    *pdf = c * p_focus / n + (1.0 - c) * p_brdf;
    return *pdf > 0.0 && isfinite(*pdf);
}
