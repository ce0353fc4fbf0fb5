/* Power-based and BSDF light sampling helpers and the path-extension blend (light_sampling.h;
 * Li et al. 2022, sections 3.3-4.2, eqs. 3-9). */
#include "transport/surface/blue_noise/light_sampling.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

vbl_result vbl_bn_light_set_init(vbl_bn_light_set* s, const vbl_bn_light* lights, size_t count,
                                 const vbl_vec3* power, double alpha)
{
    memset(s, 0, sizeof *s);
    if (!(alpha > 0.0) || !isfinite(alpha))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise light set: alpha = %g must be finite and > 0", alpha);
    s->lights = lights;
    s->count = count;
    s->alpha = alpha;
    s->cdf = (double*)malloc((count + 1) * sizeof(double));
    s->positions = (vbl_vec3*)malloc((count ? count : 1) * sizeof(vbl_vec3));
    if (!s->cdf || !s->positions) {
        vbl_bn_light_set_free(s);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise light set: cannot allocate %zu lights", count);
    }
    s->cdf[0] = 0.0;
    for (size_t j = 0; j < count; ++j) {
        double p = 1.0;
        if (power) {
            p = (power[j].x + power[j].y + power[j].z) / 3.0;
            if (!(p >= 0.0) || !isfinite(p)) {
                vbl_bn_light_set_free(s);
                return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise light set: power[%zu] = %g is not finite and >= 0", j,
                                 p);
            }
        }
        s->cdf[j + 1] = s->cdf[j] + p;
        s->positions[j] = lights[j].position;
        if (lights[j].radius > s->max_radius) s->max_radius = lights[j].radius;
    }
    s->total = s->cdf[count];
    vbl_result rc = vbl_bn_kdtree_build(&s->tree, s->positions, NULL, count);
    if (rc == VBL_SUCCESS) rc = vbl_bn_tree_set_light_radii(&s->tree, lights, count);
    if (rc != VBL_SUCCESS) vbl_bn_light_set_free(s);
    return rc;
}

void vbl_bn_light_set_free(vbl_bn_light_set* s)
{
    vbl_bn_kdtree_free(&s->tree);
    free(s->cdf);
    free(s->positions);
    s->cdf = NULL;
    s->positions = NULL;
    s->count = 0;
}

size_t vbl_bn_pick_light(const vbl_bn_light_set* s, double u, double* prob)
{
    if (!(s->total > 0.0) || s->count == 0) {
        if (prob) *prob = 0.0;
        return s->count;
    }
    double target = u * s->total;
    size_t lo = 0, hi = s->count; /* first j with cdf[j + 1] > target */
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->cdf[mid + 1] > target) hi = mid;
        else lo = mid + 1;
    }
    if (lo >= s->count) lo = s->count - 1;
    while (lo > 0 && !(s->cdf[lo + 1] > s->cdf[lo])) --lo; /* u -> 1 rounding: a light with power */
    if (prob) *prob = (s->cdf[lo + 1] - s->cdf[lo]) / s->total;
    return lo;
}

double vbl_bn_light_prob(const vbl_bn_light_set* s, size_t j)
{
    if (j >= s->count || !(s->total > 0.0)) return 0.0;
    return (s->cdf[j + 1] - s->cdf[j]) / s->total;
}

/* cos of the cone half-angle (-1: the whole sphere, x inside) and 1 - cos without cancellation
 * (sin^2 / (1 + cos)) for tiny cones. */
static double cone_cos(vbl_vec3 x, vbl_vec3 c, double r, vbl_vec3* axis, double* one_minus)
{
    vbl_vec3 d = vbl_v3_sub(c, x);
    double dist2 = vbl_v3_dot(d, d);
    *axis = vbl_v3_normalize(d);
    if (!(dist2 > r * r)) {
        *one_minus = 2.0;
        return -1.0;
    }
    double sin2 = r * r / dist2, cmax = sqrt(fmax(0.0, 1.0 - sin2));
    *one_minus = sin2 / (1.0 + cmax);
    return cmax;
}

int vbl_bn_sample_cone(vbl_vec3 x, vbl_vec3 c, double r, double u1, double u2, vbl_vec3* w, double* pdf)
{
    vbl_vec3 axis;
    double one_minus;
    cone_cos(x, c, r, &axis, &one_minus);
    double solid = 2.0 * VBL_PI * one_minus; /* > 0 for r > 0 */
    if (!(solid > 0.0)) return 0;
    double ct = 1.0 - u1 * one_minus, st = sqrt(fmax(0.0, 1.0 - ct * ct)), phi = 2.0 * VBL_PI * u2;
    vbl_vec3 t, b;
    vbl_v3_basis(axis, &t, &b);
    *w = vbl_v3_normalize(
        vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, st * cos(phi)), vbl_v3_scale(b, st * sin(phi))), vbl_v3_scale(axis, ct)));
    *pdf = 1.0 / solid;
    return 1;
}

double vbl_bn_cone_pdf(vbl_vec3 x, vbl_vec3 c, double r, vbl_vec3 w)
{
    vbl_vec3 axis;
    double one_minus, cmax = cone_cos(x, c, r, &axis, &one_minus);
    double solid = 2.0 * VBL_PI * one_minus;
    if (!(solid > 0.0) || vbl_v3_dot(w, axis) < cmax) return 0.0;
    return 1.0 / solid;
}

typedef struct contain_ctx {
    const vbl_bn_light_set* s;
    vbl_bn_kdtree_visit_fn visit;
    void* ctx;
    double sum;
    size_t n;
} contain_ctx;

static void contain_visit(void* ctx, size_t j, double d2)
{
    contain_ctx* c = (contain_ctx*)ctx;
    double r = c->s->lights[j].radius;
    if (d2 <= r * r) c->visit(c->ctx, j, d2);
}

void vbl_bn_lights_containing(const vbl_bn_light_set* s, vbl_vec3 y, vbl_bn_kdtree_visit_fn visit, void* ctx)
{
    contain_ctx c = {s, visit, ctx, 0.0, 0};
    /* radius queries are strict (d < R): widen by a relative ulp-scale margin, then test d <= r */
    vbl_bn_kdtree_within(&s->tree, y, s->max_radius * (1.0 + 1e-12), contain_visit, &c);
}

double vbl_bn_light_density(double radius, double alpha)
{
    return radius > 0.0 ? alpha * alpha / (2.0 * sqrt(3.0) * radius * radius) : 0.0;
}

typedef struct density_ctx { const vbl_bn_light_set* s; double sum; size_t n; } density_ctx;

static void density_visit(void* ctx, size_t j, double d2)
{
    (void)d2;
    density_ctx* c = (density_ctx*)ctx;
    c->sum += vbl_bn_light_density(c->s->lights[j].radius, c->s->alpha);
    ++c->n;
}

double vbl_bn_density_at(const vbl_bn_light_set* s, vbl_vec3 y, size_t* n)
{
    density_ctx c = {s, 0.0, 0};
    vbl_bn_lights_containing(s, y, density_visit, &c);
    if (n) *n = c.n;
    return c.n ? c.sum / (double)c.n : 0.0;
}

double vbl_bn_virtual_light_weight(double dist2, double pdf_bsdf, double cos_r, double density, double n_min,
                                   double n_max)
{
    if (!(density > 0.0)) return 0.0;
    double denom = pdf_bsdf * fabs(cos_r), num = dist2 * density; /* a rho = num / denom (eq 7-8) */
    if (!(n_max > n_min)) return num >= n_min * denom ? 1.0 : 0.0;
    if (num >= n_max * denom) return 1.0; /* includes denom = 0 */
    if (num <= n_min * denom) return 0.0;
    return vbl_clamp((num / denom - n_min) / (n_max - n_min), 0.0, 1.0); /* eq 9 */
}
