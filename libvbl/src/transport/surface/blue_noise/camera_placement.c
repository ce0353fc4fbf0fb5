/* Candidate virtual-light positions from camera sub-paths (camera_placement.h; section 3.1). */
#include "transport/surface/blue_noise/camera_placement.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "transport/surface/blue_noise/stop_latch.h"
#include "core/rng.h"

int vbl_bn_highly_specular(const vbl_material* m, const vbl_bn_placement_options* o)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG: return vbl_v3_max_component(m->specular) > 0.0 && m->exponent >= o->phong_exponent;
    case VBL_MATERIAL_GGX: return m->roughness <= o->ggx_roughness;
    default: return 0;
    }
}

static double mean3(vbl_vec3 v) { return (v.x + v.y + v.z) / 3.0; }

/* The sampled direction is a specular reflection: f dominated by the specular lobe. */
static int specular_pick(const vbl_material* m, vbl_vec3 f)
{
    return mean3(f) > 2.0 * mean3(m->albedo) * VBL_INV_PI;
}

static vbl_vec3 spawn(const vbl_surfaces* s, vbl_vec3 p, vbl_vec3 ng, vbl_vec3 w)
{
    double eps = vbl_surfaces_ray_epsilon(s, p);
    return vbl_v3_madd(p, ng, vbl_v3_dot(ng, w) >= 0.0 ? eps : -eps);
}

enum { OUT_NONE = 0, OUT_CANDIDATE, OUT_PRIMARY_MISS, OUT_SECONDARY_MISS, OUT_ABSORBED };

static int trace_one(const vbl_scene* scene, const vbl_bn_placement_options* o, size_t k, vbl_bn_candidate* c)
{
    const vbl_camera* cam = &scene->camera;
    const uint64_t pixels = (uint64_t)cam->width * (uint64_t)cam->height;
    const uint64_t pixel = (uint64_t)k * pixels / (uint64_t)o->candidates;
    vbl_rng rng = vbl_rng_make(o->seed, VBL_BN_PLACEMENT_STREAM, (uint64_t)k);
    double sx = (double)(pixel % (uint64_t)cam->width) + vbl_rng_uniform(&rng);
    double sy = (double)(pixel / (uint64_t)cam->width) + vbl_rng_uniform(&rng);
    vbl_vec3 origin, dir;
    vbl_camera_ray(cam, sx, sy, &origin, &dir);
    vbl_surface_hit hit;
    if (!vbl_surfaces_intersect(scene->surfaces, origin, dir, 0.0, INFINITY, &hit)) return OUT_PRIMARY_MISS;
    for (int depth = 0;; ++depth) {
        const vbl_material* m = &scene->materials[hit.material];
        vbl_vec3 wo = vbl_v3_scale(dir, -1.0), wi, f;
        double pdf = 0.0;
        double u0 = vbl_rng_uniform(&rng), u1 = vbl_rng_uniform(&rng), u2 = vbl_rng_uniform(&rng);
        if (!vbl_material_sample(m, hit.shading_normal, wo, u0, u1, u2, &wi, &pdf, &f) || !(pdf > 0.0) ||
            !(vbl_v3_dot(wi, hit.geometric_normal) > 0.0))
            return OUT_ABSORBED;
        vbl_vec3 x = hit.position;
        vbl_vec3 from = spawn(scene->surfaces, x, hit.geometric_normal, wi);
        int extend = depth < o->max_specular_depth && vbl_bn_highly_specular(m, o) && specular_pick(m, f);
        vbl_surface_hit next;
        if (!vbl_surfaces_intersect(scene->surfaces, from, wi, 0.0, INFINITY, &next)) return OUT_SECONDARY_MISS;
        dir = wi;
        if (extend) {
            hit = next;
            continue;
        }
        c->position = next.position;
        c->normal = next.shading_normal;
        c->from = x;
        c->material = next.material;
        c->surface = next.surface;
        c->depth = depth;
        c->pixel = (uint32_t)pixel;
        return OUT_CANDIDATE;
    }
}

vbl_result vbl_bn_place_candidates(const vbl_scene* scene, const vbl_bn_placement_options* options,
                                   vbl_bn_candidate** out, size_t* count, vbl_bn_placement_stats* stats)
{
    vbl_bn_placement_options defaults = VBL_BN_PLACEMENT_DEFAULT;
    const vbl_bn_placement_options* o = options ? options : &defaults;
    *out = NULL;
    *count = 0;
    if (o->size < sizeof(vbl_bn_placement_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise placement: options.size = %zu is too small", o->size);
    if (!scene->surfaces || scene->surface_count <= 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise placement: scene '%s' has no surfaces", scene->path);
    if (o->candidates == 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise placement: options.candidates must be > 0");
    if (o->max_specular_depth < 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise placement: options.max_specular_depth = %d must be >= 0",
                         o->max_specular_depth);
    if (scene->camera.width <= 0 || scene->camera.height <= 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise placement: scene '%s': camera resolution %dx%d",
                         scene->path, scene->camera.width, scene->camera.height);
    const size_t M = o->candidates;
    vbl_bn_candidate* slots = (vbl_bn_candidate*)malloc(M * sizeof(vbl_bn_candidate));
    unsigned char* kind = (unsigned char*)malloc(M);
    if (!slots || !kind) {
        free(slots);
        free(kind);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise placement: cannot allocate %zu candidates", M);
    }
    int stopped = 0; /* o->stop said stop: the remaining sub-paths are skipped */
#pragma omp parallel for schedule(dynamic, 256)
    for (long long k = 0; k < (long long)M; ++k) {
        if (vbl_bn_stop_latch(&stopped, k, o->stop, o->stop_user)) continue;
        kind[k] = (unsigned char)trace_one(scene, o, (size_t)k, &slots[k]);
    }
    if (stopped) {
        free(slots);
        free(kind);
        return vbl_error(VBL_ERROR_INTERRUPTED, "blue noise placement: stopped (cancel or time limit)");
    }
    vbl_bn_placement_stats s;
    memset(&s, 0, sizeof s);
    s.traced = M;
    size_t n = 0;
    for (size_t k = 0; k < M; ++k) {
        switch (kind[k]) {
        case OUT_CANDIDATE:
            if (slots[k].depth > 0) ++s.extended;
            slots[n++] = slots[k];
            break;
        case OUT_PRIMARY_MISS: ++s.primary_misses; break;
        case OUT_SECONDARY_MISS: ++s.secondary_misses; break;
        default: ++s.absorbed; break;
        }
    }
    free(kind);
    if (stats) *stats = s;
    if (n == 0) {
        free(slots);
        return VBL_SUCCESS;
    }
    vbl_bn_candidate* shrunk = (vbl_bn_candidate*)realloc(slots, n * sizeof(vbl_bn_candidate));
    *out = shrunk ? shrunk : slots;
    *count = n;
    return VBL_SUCCESS;
}
