/* surface_from_volume kernels: VRL eq 6 (section 4.3), VBL eqs 8-9 (section 3.1). */
#include "transport/surface/surface_from_volume.h"

#include <stddef.h>

#include "sampling/phase_hg.h"
#include "sampling/vsl_cone.h"
#include "transport/surface/surface_cone_kernel.h"

void vbl_surface_point_init(vbl_surface_point* sp, vbl_vec3 position, vbl_vec3 normal, vbl_vec3 wo,
                            const vbl_material* material)
{
    sp->position = position;
    sp->normal = normal;
    sp->wo = wo;
    sp->material = material;
    sp->max_direction = vbl_material_max_direction(material, normal, wo);
}

static double mean3(vbl_vec3 v) { return (v.x + v.y + v.z) * (1.0 / 3.0); }

vbl_vec3 vbl_vrl_surface_integrand(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, double v)
{
    vbl_vec3 p = vbl_v3_madd(vrl->origin, vrl->direction, v);
    vbl_vec3 wi = vbl_v3_sub(p, sp->position);
    double w2 = vbl_v3_dot(wi, wi);
    if (!(w2 > 0.0)) return vbl_v3(0, 0, 0);
    wi = vbl_v3_scale(wi, 1.0 / sqrt(w2));
    double c = vbl_v3_dot(sp->normal, wi);
    if (!(c > 0.0)) return vbl_v3(0, 0, 0);
    double ph = vbl_hg_eval(vrl->g, -vbl_v3_dot(vrl->direction, wi)); /* omega = -wi */
    return vbl_v3_scale(vbl_material_eval(sp->material, sp->normal, sp->wo, wi), ph * c / w2);
}

vbl_vec3 vbl_beam_light_surface_kernel(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, double v, double radius,
                                int n, const double jitter[3])
{
    if (!(radius > 0.0)) return vbl_vrl_surface_integrand(sp, vrl, v);
    vbl_surface_lobe a = vbl_surface_lobe_receiver(sp->material, sp->normal, sp->wo);
    vbl_surface_lobe b = vbl_surface_lobe_phase(vrl->g, vrl->direction);
    return vbl_surface_cone_kernel(&a, &b, sp->position, vbl_v3_madd(vrl->origin, vrl->direction, v), radius, n,
                                   jitter);
}

vbl_vec3 vbl_surface_vrl_mixture_kernel(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, double v,
                                        double radius, int n, const double jitter[3], const vbl_medium_point* mp)
{
    vbl_vec3 k = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < mp->count; ++i) {
        vbl_surface_vrl lobe = *vrl;
        lobe.g = mp->lobe[i].g;
        vbl_vec3 ki = radius > 0.0 ? vbl_beam_light_surface_kernel(sp, &lobe, v, radius, n, jitter)
                                   : vbl_vrl_surface_integrand(sp, &lobe, v);
        k = vbl_v3_add(k, vbl_v3_mul(vbl_medium_lobe_weight(mp, i), ki));
    }
    return k;
}

typedef struct target_ctx {
    const vbl_surface_point* sp;
    const vbl_surface_vrl* vrl;
    double radius;
    const vbl_medium_point* hint; /* NULL: one HG lobe of the VRL's g */
} target_ctx;

/* The target's phase value at cos: HG(g) or the hint's mixture pdf. */
static double target_phase(const target_ctx* t, double c)
{
    return t->hint ? vbl_medium_phase_pdf(t->hint, c) : vbl_hg_eval(t->vrl->g, c);
}

/* VRL target (angular measure): HG x mean(f cos) at the VRL point. */
static double vrl_target(void* c, vbl_vec3 p)
{
    const target_ctx* t = (const target_ctx*)c;
    vbl_vec3 wi = vbl_v3_normalize(vbl_v3_sub(p, t->sp->position));
    double cs = vbl_v3_dot(t->sp->normal, wi);
    if (!(cs > 0.0)) return 0.0;
    double ph = target_phase(t, -vbl_v3_dot(t->vrl->direction, wi));
    return ph * cs * mean3(vbl_material_eval(t->sp->material, t->sp->normal, t->sp->wo, wi));
}

/* VBL target: max of HG over the VSL's cone x max of f cos over it (section 3.1). */
static double vbl_target(void* c, vbl_vec3 p)
{
    const target_ctx* t = (const target_ctx*)c;
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(t->sp->position, p), t->radius, vbl_v3_scale(t->sp->normal, -1.0)))
        return 0.0;
    double ph = 0.0;
    if (!t->hint) {
        ph = vbl_vsl_cone_hg_max(&cone, t->vrl->g, t->vrl->direction, NULL);
    } else { /* an upper bound of the mixture's maximum: the q-weighted lobe maxima */
        double total = 0.0;
        for (int i = 0; i < t->hint->count; ++i) {
            const vbl_phase_lobe* l = &t->hint->lobe[i];
            double q = l->sigma_t * mean3(l->albedo);
            total += q;
            ph += q * vbl_vsl_cone_hg_max(&cone, l->g, t->vrl->direction, NULL);
        }
        ph = total > 0.0 ? ph / total : 0.0;
    }
    vbl_vec3 f = vbl_material_max_in_cone(t->sp->material, t->sp->normal, t->sp->wo, vbl_v3_scale(cone.axis, -1.0),
                                          cone.cos_half);
    return ph * mean3(f);
}

static int sampler_init(vbl_surface_line_sampler* s, const vbl_surface_point* sp, const vbl_surface_vrl* vrl,
                        double radius, const vbl_medium_point* hint)
{
    double r = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    if (!vbl_surface_line_init(s, vrl->origin, vrl->direction, 0.0, vrl->length, sp->position, r)) return 0;
    double hints[2];
    int nh = 0;
    if (vbl_surface_line_angle_toward(s, sp->max_direction, &hints[nh])) ++nh;
    if (vbl_surface_line_angle_horizon(s, sp->normal, &hints[nh])) ++nh;
    target_ctx t = {sp, vrl, r, hint && hint->count > 0 ? hint : NULL};
    vbl_surface_line_fit(s, hints, nh, r > 0.0 ? vbl_target : vrl_target, &t);
    return 1;
}

int vbl_surface_vrl_sampler_init(vbl_surface_line_sampler* s, const vbl_surface_point* sp,
                                 const vbl_surface_vrl* vrl, double radius)
{
    return sampler_init(s, sp, vrl, radius, NULL);
}

int vbl_surface_vrl_sampler_init_mixture(vbl_surface_line_sampler* s, const vbl_surface_point* sp,
                                         const vbl_surface_vrl* vrl, double radius, const vbl_medium_point* hint)
{
    return sampler_init(s, sp, vrl, radius, hint);
}

static vbl_vec3 estimate(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, const vbl_surface_kernel* kernel,
                         vbl_surface_medium_fn medium, void* ctx, double xi, double* v_out, double* pdf_out)
{
    const double radius = kernel->radius;
    vbl_vec3 zero = vbl_v3(0, 0, 0);
    vbl_surface_line_sampler s;
    double pdf = 0.0, v = 0.0;
    if (vbl_surface_vrl_sampler_init(&s, sp, vrl, radius)) v = vbl_surface_line_sample(&s, xi, &pdf);
    if (v_out) *v_out = v;
    if (pdf_out) *pdf_out = pdf;
    if (!(pdf > 0.0)) return zero;
    vbl_vec3 p = vbl_surface_line_point(&s, v);
    double m = medium(ctx, v, p, sp->position);
    if (!(m > 0.0)) return zero;
    vbl_vec3 k = radius > 0.0 ? vbl_beam_light_surface_kernel(sp, vrl, v, radius, kernel->n, kernel->jitter)
                              : vbl_vrl_surface_integrand(sp, vrl, v);
    return vbl_v3_scale(vbl_v3_mul(vrl->power, k), m / pdf);
}

vbl_vec3 vbl_surface_from_vrl(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, vbl_surface_medium_fn medium,
                              void* ctx, double xi, double* v_out, double* pdf_out)
{
    const vbl_surface_kernel point = {0.0, 1, {0, 0, 0}};
    return estimate(sp, vrl, &point, medium, ctx, xi, v_out, pdf_out);
}

vbl_vec3 vbl_surface_from_vbl(const vbl_surface_point* sp, const vbl_surface_vrl* vrl, const vbl_surface_kernel* kernel,
                              vbl_surface_medium_fn medium, void* ctx, double xi, double* v_out, double* pdf_out)
{
    vbl_surface_kernel k = *kernel;
    k.radius = (k.radius > 0.0 && isfinite(k.radius)) ? k.radius : 0.0;
    return estimate(sp, vrl, &k, medium, ctx, xi, v_out, pdf_out);
}

vbl_vec3 vbl_surface_from_vrl_mixture(const vbl_surface_point* sp, const vbl_surface_vrl* vrl,
                                      const vbl_surface_kernel* kernel, const vbl_medium_point* hint,
                                      vbl_surface_mixture_fn medium, void* ctx, double xi)
{
    vbl_vec3 zero = vbl_v3(0, 0, 0);
    const double radius = kernel->radius, r = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    vbl_surface_line_sampler s;
    double pdf = 0.0, v = 0.0;
    if (sampler_init(&s, sp, vrl, r, hint)) v = vbl_surface_line_sample(&s, xi, &pdf);
    if (!(pdf > 0.0)) return zero;
    vbl_medium_point mp;
    mp.count = 0;
    double m = medium(ctx, v, vbl_surface_line_point(&s, v), sp->position, &mp);
    if (!(m > 0.0) || mp.count == 0) return zero;
    vbl_vec3 k = vbl_surface_vrl_mixture_kernel(sp, vrl, v, r, kernel->n, kernel->jitter, &mp);
    return vbl_v3_scale(vbl_v3_mul(vrl->power, k), m / pdf);
}
