/* Surface VSLs: store, surface_from_surface (VBL section 3.4), volume_from_surface (section 3.3). */
#include "transport/surface/surface_vsl.h"

#include <stdlib.h>

#include "core/error.h"
#include "sampling/phase_hg.h"
#include "sampling/vsl_cone.h"
#include "transport/surface/surface_cone_kernel.h"

void vbl_surface_vsl_store_init(vbl_surface_vsl_store* store, const vbl_material* materials, size_t material_count)
{
    store->vsls = NULL;
    store->count = store->capacity = 0;
    store->materials = materials;
    store->material_count = material_count;
}

static int unit(vbl_vec3 v) { return isfinite(vbl_v3_length(v)) && fabs(vbl_v3_length(v) - 1.0) <= 1e-6; }

vbl_result vbl_surface_vsl_store_add(vbl_surface_vsl_store* store, const vbl_surface_vsl* vsl)
{
    if (vsl->material < 0 || (size_t)vsl->material >= store->material_count)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "surface VSL %zu: material = %d is outside [0, %zu)",
                         store->count, vsl->material, store->material_count);
    vbl_vec3 p = vsl->power;
    if (!(p.x >= 0.0 && p.y >= 0.0 && p.z >= 0.0 && isfinite(p.x + p.y + p.z)))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "surface VSL %zu: power = (%g, %g, %g) is not finite and >= 0",
                         store->count, p.x, p.y, p.z);
    if (!unit(vsl->normal) || !unit(vsl->incident) ||
        !isfinite(vsl->position.x + vsl->position.y + vsl->position.z))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "surface VSL %zu: position must be finite, normal and incident unit vectors", store->count);
    if (store->count == store->capacity) {
        size_t cap = store->capacity ? 2 * store->capacity : 256;
        vbl_surface_vsl* v = (vbl_surface_vsl*)realloc(store->vsls, cap * sizeof(*v));
        if (!v)
            return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "surface VSLs: cannot grow the store to %zu entries", cap);
        store->vsls = v;
        store->capacity = cap;
    }
    store->vsls[store->count++] = *vsl;
    return VBL_SUCCESS;
}

void vbl_surface_vsl_store_free(vbl_surface_vsl_store* store)
{
    free(store->vsls);
    store->vsls = NULL;
    store->count = store->capacity = 0;
}

vbl_vec3 vbl_surface_vsl_kernel_surface(const vbl_surface_point* sp, const vbl_surface_vsl* vsl,
                                        const vbl_material* vm, double radius, int n, const double jitter[3])
{
    vbl_surface_lobe a = vbl_surface_lobe_receiver(sp->material, sp->normal, sp->wo);
    vbl_surface_lobe b = vbl_surface_lobe_sender(vm, vsl->normal, vsl->incident);
    return vbl_surface_cone_kernel(&a, &b, sp->position, vsl->position, radius, n, jitter);
}

vbl_vec3 vbl_surface_vsl_kernel_medium(vbl_vec3 x, vbl_vec3 c_d, double g_camera, const vbl_surface_vsl* vsl,
                                       const vbl_material* vm, double radius, int n, const double jitter[3])
{
    vbl_surface_lobe a = vbl_surface_lobe_phase(g_camera, vbl_v3_scale(c_d, -1.0));
    vbl_surface_lobe b = vbl_surface_lobe_sender(vm, vsl->normal, vsl->incident);
    return vbl_surface_cone_kernel(&a, &b, x, vsl->position, radius, n, jitter);
}

vbl_vec3 vbl_surface_from_surface(const vbl_surface_point* sp, const vbl_surface_vsl_store* store, double radius,
                                  vbl_surface_visibility_fn visibility, void* ctx, int n, vbl_rng* rng)
{
    vbl_vec3 sum = vbl_v3(0, 0, 0);
    for (size_t i = 0; i < store->count; ++i) {
        const vbl_surface_vsl* vsl = &store->vsls[i];
        double jitter[3] = {vbl_rng_uniform(rng), vbl_rng_uniform(rng), vbl_rng_uniform(rng)};
        vbl_vec3 k = vbl_surface_vsl_kernel_surface(sp, vsl, &store->materials[vsl->material], radius, n, jitter);
        if (k.x == 0.0 && k.y == 0.0 && k.z == 0.0) continue;
        double t = visibility ? visibility(ctx, vsl->position, sp->position) : 1.0;
        if (!(t > 0.0)) continue;
        sum = vbl_v3_add(sum, vbl_v3_scale(vbl_v3_mul(vsl->power, k), t));
    }
    return sum;
}

typedef struct camera_target {
    vbl_vec3 c_d;
    double g_camera, radius;
    const vbl_surface_vsl* vsl;
    const vbl_material* vm;
} camera_target;

/* Angular-measure target at the camera point p: HG at p x the VSL's f cos (R > 0: cone maxima). */
static double camera_target_fn(void* c, vbl_vec3 p)
{
    const camera_target* t = (const camera_target*)c;
    vbl_surface_lobe a = vbl_surface_lobe_phase(t->g_camera, vbl_v3_scale(t->c_d, -1.0));
    vbl_surface_lobe b = vbl_surface_lobe_sender(t->vm, t->vsl->normal, t->vsl->incident);
    vbl_vsl_cone cone;
    if (!vbl_vsl_cone_init(&cone, vbl_v3_sub(p, t->vsl->position), t->radius, t->vsl->normal)) return 0.0;
    return vbl_surface_lobe_max_in_cone(&a, &cone) * vbl_surface_lobe_max_in_cone(&b, &cone);
}

int vbl_surface_vsl_camera_sampler_init(vbl_surface_line_sampler* s, const vbl_segment* camera, double g_camera,
                                        const vbl_surface_vsl* vsl, const vbl_material* vm, double radius)
{
    const vbl_vec3 c_o = camera->origin, c_d = camera->direction;
    const double u0 = camera->t0, u1 = camera->t1;
    double r = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    if (!vbl_surface_line_init(s, c_o, c_d, u0, u1, vsl->position, r)) return 0;
    double hints[2];
    int nh = 0;
    /* the VSL's peak: f(omega, wi) cos(omega) is maximal at max_direction(m, n, wi) (reciprocity) */
    vbl_vec3 peak = vbl_material_max_direction(vm, vsl->normal, vsl->incident);
    if (vbl_surface_line_angle_toward(s, peak, &hints[nh])) ++nh;
    if (vbl_surface_line_angle_horizon(s, vsl->normal, &hints[nh])) ++nh;
    camera_target t = {c_d, g_camera, r, vsl, vm};
    vbl_surface_line_fit(s, hints, nh, camera_target_fn, &t);
    return 1;
}

vbl_vec3 vbl_volume_from_vsl(const vbl_segment* camera, double g_camera, const vbl_surface_vsl* vsl,
                             const vbl_material* vm, const vbl_surface_kernel* kernel, vbl_surface_camera_medium medium,
                             double xi, double* u_out, double* pdf_out)
{
    vbl_vec3 zero = vbl_v3(0, 0, 0);
    const double radius = kernel->radius;
    double r = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    vbl_surface_line_sampler s;
    double pdf = 0.0, u = camera->t0;
    if (vbl_surface_vsl_camera_sampler_init(&s, camera, g_camera, vsl, vm, r))
        u = vbl_surface_line_sample(&s, xi, &pdf);
    if (u_out) *u_out = u;
    if (pdf_out) *pdf_out = pdf;
    if (!(pdf > 0.0)) return zero;
    vbl_vec3 x = vbl_surface_line_point(&s, u);
    double m = medium.fn(medium.ctx, u, x, vsl->position);
    if (!(m > 0.0)) return zero;
    vbl_vec3 k = vbl_surface_vsl_kernel_medium(x, camera->direction, g_camera, vsl, vm, r, kernel->n, kernel->jitter);
    return vbl_v3_scale(vbl_v3_mul(vsl->power, k), m / pdf);
}

vbl_vec3 vbl_volume_from_surface(const vbl_segment* camera, double g_camera, const vbl_surface_vsl_store* store,
                                 double radius, vbl_surface_camera_medium medium, int n, vbl_rng* rng)
{
    vbl_vec3 sum = vbl_v3(0, 0, 0);
    for (size_t i = 0; i < store->count; ++i) {
        const vbl_surface_vsl* vsl = &store->vsls[i];
        double xi = vbl_rng_uniform(rng);
        vbl_surface_kernel kernel = {radius, n, {0.0, 0.0, 0.0}};
        for (int k = 0; k < 3; ++k) kernel.jitter[k] = vbl_rng_uniform(rng);
        sum = vbl_v3_add(sum, vbl_volume_from_vsl(camera, g_camera, vsl, &store->materials[vsl->material], &kernel,
                                                  medium, xi, NULL, NULL));
    }
    return sum;
}
