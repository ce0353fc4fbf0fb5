/* Photon-light shading with power and BSDF sampling, MIS and the path-extension weight (gather.h). */
#include "transport/surface/blue_noise/gather.h"

#include <string.h>

#include "sampling/phase_hg.h"

static vbl_vec3 spawn(const vbl_bn_shading* sp, vbl_vec3 w)
{
    if (!sp->material) return sp->position;
    return vbl_v3_madd(sp->position, sp->geometric_normal,
                       vbl_v3_dot(sp->geometric_normal, w) >= 0.0 ? sp->ray_epsilon : -sp->ray_epsilon);
}

/* The scattering at x for light arriving from direction w (towards the light) and leaving to wo:
 * the BSDF at surfaces, the medium's value at medium points. Light travels along -w, then along
 * wo: the phase cosine is dot(-w, wo). */
static vbl_vec3 scatter_f(const vbl_bn_shading* sp, vbl_vec3 w)
{
    if (sp->material) return vbl_material_eval(sp->material, sp->normal, sp->wo, w);
    return sp->medium_f(sp->medium_ctx, -vbl_v3_dot(w, sp->wo));
}

static double scatter_pdf(const vbl_bn_shading* sp, vbl_vec3 w)
{
    if (sp->material) return vbl_material_pdf(sp->material, sp->normal, sp->wo, w);
    return vbl_hg_pdf(sp->phase_g, -vbl_v3_dot(w, sp->wo));
}

/* 1 with the direction, pdf and value; the camera path travels along -wo, then along w. */
static int scatter_sample(const vbl_bn_shading* sp, const double u[3], vbl_vec3* w, double* pdf, vbl_vec3* f)
{
    if (sp->material) return vbl_material_sample(sp->material, sp->normal, sp->wo, u[0], u[1], u[2], w, pdf, f);
    *w = vbl_hg_sample(sp->phase_g, vbl_v3_scale(sp->wo, -1.0), u[0], u[1], pdf);
    *f = scatter_f(sp, *w);
    return *pdf > 0.0;
}

/* cos_x (1 in media) and whether w leaves on the viewer's side (always in media). */
static double scatter_cos(const vbl_bn_shading* sp, vbl_vec3 w)
{
    if (!sp->material) return 1.0;
    double c = vbl_v3_dot(sp->normal, w);
    return c > 0.0 && vbl_v3_dot(sp->geometric_normal, w) > 0.0 ? c : 0.0;
}

typedef struct bsdf_ctx {
    const vbl_bn_light_set* set;
    const vbl_bn_emission* e;
    vbl_vec3 x, w;
    double pdf_b;
    vbl_vec3 sum;
} bsdf_ctx;

static void bsdf_visit(void* ctx, size_t i, double d2)
{
    (void)d2;
    bsdf_ctx* c = (bsdf_ctx*)ctx;
    const vbl_bn_light* l = &c->set->lights[i];
    double p_i = vbl_bn_light_prob(c->set, i) * vbl_bn_cone_pdf(c->x, l->position, l->radius, c->w);
    double mis = vbl_bn_power_heuristic(c->pdf_b, p_i);
    vbl_vec3 I = vbl_bn_emission_intensity(c->e, i, vbl_v3_scale(c->w, -1.0));
    c->sum = vbl_v3_madd(c->sum, I, mis);
}

void vbl_bn_gather(const vbl_bn_light_set* set, const vbl_bn_emission* e, const vbl_bn_shading* sp,
                   vbl_bn_trace_fn trace, void* ctx, const double u[6], double n_min, double n_max,
                   vbl_bn_gather_result* out)
{
    memset(out, 0, sizeof *out);
    const vbl_vec3 x = sp->position, n = sp->normal;

    /* ---- power-based light sample (eq 4) ---- */
    double prob = 0.0;
    size_t j = vbl_bn_pick_light(set, u[0], &prob);
    vbl_vec3 w;
    double cone_pdf = 0.0;
    if (j < set->count && prob > 0.0 &&
        vbl_bn_sample_cone(x, set->lights[j].position, set->lights[j].radius, u[1], u[2], &w, &cone_pdf)) {
        double cos_x = scatter_cos(sp, w), p_j = prob * cone_pdf;
        vbl_vec3 y = x, ny = n;
        if (cos_x > 0.0 && p_j > 0.0 && trace(ctx, spawn(sp, w), w, &y, &ny)) {
            vbl_vec3 d = vbl_v3_sub(y, set->lights[j].position);
            double r = set->lights[j].radius;
            if (vbl_v3_dot(d, d) <= r * r) { /* eq 3: visible through its sphere */
                vbl_vec3 I = vbl_bn_emission_intensity(e, j, vbl_v3_scale(w, -1.0));
                if (I.x > 0.0 || I.y > 0.0 || I.z > 0.0) {
                    double pdf_b = scatter_pdf(sp, w);
                    vbl_vec3 xy = vbl_v3_sub(y, x);
                    double w_v = vbl_bn_virtual_light_weight(vbl_v3_dot(xy, xy), pdf_b, vbl_v3_dot(ny, w),
                                                             vbl_bn_density_at(set, y, NULL), n_min, n_max);
                    double mis = vbl_bn_power_heuristic(p_j, pdf_b);
                    vbl_vec3 f = scatter_f(sp, w);
                    double T = sp->transmittance ? sp->transmittance(sp->transmittance_ctx, spawn(sp, w), y) : 1.0;
                    out->L_light = vbl_v3_scale(vbl_v3_mul(f, I), T * cos_x * w_v * mis / p_j);
                }
            }
        }
    }

    /* ---- BSDF sample ---- */
    vbl_vec3 f;
    double pdf_b = 0.0;
    if (scatter_sample(sp, u + 3, &w, &pdf_b, &f) && pdf_b > 0.0) {
        double cos_x = scatter_cos(sp, w);
        if (cos_x > 0.0) {
            out->bsdf_valid = 1;
            out->bsdf_dir = w;
            out->bsdf_f = f;
            out->bsdf_pdf = pdf_b;
            out->cos_x = cos_x;
            vbl_vec3 y = x, ny = n;
            if (trace(ctx, spawn(sp, w), w, &y, &ny)) {
                out->bsdf_hit = 1;
                out->hit_position = y;
                out->hit_normal = ny;
                size_t count = 0;
                double rho = vbl_bn_density_at(set, y, &count);
                out->lights_at_hit = count;
                vbl_vec3 xy = vbl_v3_sub(y, x);
                out->w_v = vbl_bn_virtual_light_weight(vbl_v3_dot(xy, xy), pdf_b, vbl_v3_dot(ny, w), rho, n_min, n_max);
                if (count > 0 && out->w_v > 0.0) {
                    bsdf_ctx c = {set, e, x, w, pdf_b, vbl_v3(0, 0, 0)};
                    vbl_bn_lights_containing(set, y, bsdf_visit, &c);
                    double T = sp->transmittance ? sp->transmittance(sp->transmittance_ctx, spawn(sp, w), y) : 1.0;
                    out->L_bsdf = vbl_v3_scale(vbl_v3_mul(f, c.sum), T * cos_x * out->w_v / pdf_b);
                }
            }
        }
    }
    out->L = vbl_v3_add(out->L_light, out->L_bsdf);
}
