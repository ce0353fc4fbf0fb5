/* pt.light_focus: scattered directions from the BRDF or phase function mixed with focus cones about
 * point lights in media (pt_light_focus.h). */
#include "transport/path_tracing/pt_light_focus.h"

#include <math.h>

#include "sampling/focus_cone.h"
#include "scene/lights.h"
#include "scene/scene.h"

void vbl_pt_light_focus_init(const vbl_render_context* ctx, vbl_pt_light_focus* lf)
{
    lf->fraction = 0.0;
    lf->count = 0;
    const vbl_scene* scene = ctx->scene;
    const double c = ctx->options.pt.light_focus;
    vbl_vec3 lo, hi;
    if (!(c > 0.0) || !vbl_scene_media_box(scene, &lo, &hi)) return;
    for (int i = 0; i < scene->light_count && lf->count < VBL_PT_LIGHT_FOCUS_MAX; ++i)
        if (vbl_light_local_in_box(&scene->lights[i], lo, hi)) lf->light[lf->count++] = scene->lights[i].position;
    lf->radius = 0.5 * vbl_v3_length(vbl_v3_sub(hi, lo));
    if (lf->count > 0 && lf->radius > 0.0 && isfinite(lf->radius)) lf->fraction = c;
}

/* One light's cone at a vertex: axis, half-angle and its cosine. */
typedef struct vbl_pt_cone {
    vbl_vec3 axis;
    double psi_max, cos_max;
} vbl_pt_cone;

/* Light i's cone at x; 0 where x is at the light. psi_max = atan(rho / r), cos psi_max =
 * r / sqrt(r^2 + rho^2). */
static int vbl_pt_focus_cone(const vbl_pt_light_focus* lf, int i, vbl_vec3 x, vbl_pt_cone* cone)
{
    const vbl_vec3 d = vbl_v3_sub(lf->light[i], x);
    const double r = vbl_v3_length(d);
    if (!(r > 0.0) || !isfinite(r)) return 0;
    cone->axis = vbl_v3_scale(d, 1.0 / r);
    cone->psi_max = atan2(lf->radius, r); /* in (0, pi/2] */
    cone->cos_max = r / hypot(r, lf->radius);
    return cone->psi_max > 0.0 && isfinite(cone->cos_max);
}

/* The cones taking part at x (n_above: only lights above the plane of normal n through x; NULL:
 * all), and their count. */
static int vbl_pt_focus_cones(const vbl_pt_light_focus* lf, vbl_vec3 x, const vbl_vec3* n_above,
                              vbl_pt_cone cones[VBL_PT_LIGHT_FOCUS_MAX])
{
    int n = 0;
    for (int i = 0; i < lf->count; ++i) {
        if (!vbl_pt_focus_cone(lf, i, x, &cones[n])) continue;
        if (n_above && !(vbl_v3_dot(cones[n].axis, *n_above) > 0.0)) continue;
        ++n;
    }
    return n;
}

/* (1 / n) sum_j p_j(wi) over the cones */
static double vbl_pt_focus_mean_pdf(int n, const vbl_pt_cone* cones, vbl_vec3 wi)
{
    double sum = 0.0;
    for (int j = 0; j < n; ++j) sum += vbl_focus_cone_pdf_cos(cones[j].axis, cones[j].psi_max, cones[j].cos_max, wi);
    return sum / n;
}

/* A direction from cone floor(n u0 / c) of the n (u0 < c). */
static int vbl_pt_focus_pick(int n, const vbl_pt_cone* cones, double c, double u0, double u1, double u2, vbl_vec3* wi)
{
    int k = (int)(u0 / c * n);
    if (k >= n) k = n - 1;
    double pk;
    return vbl_focus_cone_sample(cones[k].axis, cones[k].psi_max, u1, u2, wi, &pk);
}

/* (u0 - c) / (1 - c): uniform in [0, 1) again for u0 in [c, 1) */
static double vbl_pt_focus_rest(double u0, double c)
{
    const double v = (u0 - c) / (1.0 - c);
    return v < 1.0 ? v : nextafter(1.0, 0.0);
}

/* ---- surface vertices ---------------------------------------------------------------------- */

double vbl_pt_light_focus_surface_pdf(const vbl_pt_light_focus* lf, const vbl_material* m, const vbl_surface_hit* hit,
                                      vbl_vec3 wo, vbl_vec3 wi)
{
    const double p = vbl_material_pdf(m, hit->shading_normal, wo, wi);
    if (!lf || !(lf->fraction > 0.0)) return p;
    vbl_pt_cone cones[VBL_PT_LIGHT_FOCUS_MAX];
    const int n = vbl_pt_focus_cones(lf, hit->position, &hit->geometric_normal, cones);
    return n > 0 ? lf->fraction * vbl_pt_focus_mean_pdf(n, cones, wi) + (1.0 - lf->fraction) * p : p;
}

double vbl_pt_light_focus_surface_pdf_fn(const void* data, const vbl_material* m, const vbl_surface_hit* hit,
                                         vbl_vec3 wo, vbl_vec3 wi)
{
    return vbl_pt_light_focus_surface_pdf(data, m, hit, wo, wi);
}

int vbl_pt_light_focus_surface_sample(const vbl_pt_light_focus* lf, const vbl_material* m,
                                      const vbl_surface_hit* hit, vbl_vec3 wo, double u0, double u1, double u2,
                                      vbl_vec3* wi, double* pdf, vbl_vec3* f)
{
    const double c = lf ? lf->fraction : 0.0;
    vbl_pt_cone cones[VBL_PT_LIGHT_FOCUS_MAX];
    const int n = c > 0.0 ? vbl_pt_focus_cones(lf, hit->position, &hit->geometric_normal, cones) : 0;
    if (n == 0) return vbl_material_sample(m, hit->shading_normal, wo, u0, u1, u2, wi, pdf, f);
    double p_brdf;
    if (u0 < c) {
        if (!vbl_pt_focus_pick(n, cones, c, u0, u1, u2, wi)) return 0;
        *f = vbl_material_eval(m, hit->shading_normal, wo, *wi);
        p_brdf = vbl_material_pdf(m, hit->shading_normal, wo, *wi);
    } else if (!vbl_material_sample(m, hit->shading_normal, wo, vbl_pt_focus_rest(u0, c), u1, u2, wi, &p_brdf, f)) {
        return 0;
    }
    /* the mixture's density from the densities' own formulas (the same function as _pdf) */
    *pdf = c * vbl_pt_focus_mean_pdf(n, cones, *wi) + (1.0 - c) * p_brdf;
    return *pdf > 0.0 && isfinite(*pdf);
}

/* ---- medium vertices ----------------------------------------------------------------------- */

vbl_pt_light_focus_vertex vbl_pt_light_focus_at_event(const vbl_pt_light_focus* lf, int events)
{
    vbl_pt_light_focus_vertex v = {lf, 0.0};
    if (lf && events <= VBL_PT_LIGHT_FOCUS_MEDIUM_EVENTS) v.c = lf->fraction;
    return v;
}

double vbl_pt_light_focus_medium_pdf(const vbl_pt_light_focus_vertex* v, const vbl_medium_point* mp, vbl_vec3 x,
                                     vbl_vec3 travel, vbl_vec3 wi)
{
    const double p = vbl_medium_phase_pdf(mp, vbl_v3_dot(travel, wi));
    if (!v || !(v->c > 0.0)) return p;
    vbl_pt_cone cones[VBL_PT_LIGHT_FOCUS_MAX];
    const int n = vbl_pt_focus_cones(v->focus, x, NULL, cones);
    return n > 0 ? v->c * vbl_pt_focus_mean_pdf(n, cones, wi) + (1.0 - v->c) * p : p;
}

double vbl_pt_light_focus_medium_pdf_fn(const void* data, const vbl_medium_point* mp, vbl_vec3 x, vbl_vec3 travel,
                                        vbl_vec3 wi)
{
    return vbl_pt_light_focus_medium_pdf(data, mp, x, travel, wi);
}

int vbl_pt_light_focus_medium_sample(const vbl_pt_light_focus_vertex* v, const vbl_medium_point* mp, vbl_vec3 x,
                                     vbl_vec3 travel, double u0, double u1, double u2, vbl_vec3* wi, double* pdf)
{
    const double c = v ? v->c : 0.0;
    vbl_pt_cone cones[VBL_PT_LIGHT_FOCUS_MAX];
    const int n = c > 0.0 ? vbl_pt_focus_cones(v->focus, x, NULL, cones) : 0;
    if (n == 0) return vbl_medium_phase_sample(mp, travel, u0, u1, u2, wi, pdf);
    if (u0 < c) {
        if (!vbl_pt_focus_pick(n, cones, c, u0, u1, u2, wi)) return 0;
    } else if (!vbl_medium_phase_sample(mp, travel, vbl_pt_focus_rest(u0, c), u1, u2, wi, pdf)) {
        return 0;
    }
    *pdf = c * vbl_pt_focus_mean_pdf(n, cones, *wi) + (1.0 - c) * vbl_medium_phase_pdf(mp, vbl_v3_dot(travel, *wi));
    return *pdf > 0.0 && isfinite(*pdf);
}
