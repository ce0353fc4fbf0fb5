/* Candidates -> blue-noise virtual lights (blue_noise_lights.h). */
#include "transport/surface/blue_noise/blue_noise_lights.h"

#include <stdlib.h>

#include "core/error.h"

vbl_result vbl_bn_lights_from_candidates(const vbl_bn_candidate* candidates, size_t count, size_t N, double alpha,
                                         const vbl_material* materials, size_t material_count,
                                         const vbl_bn_elimination_options* elimination, vbl_bn_light** out,
                                         size_t* out_count)
{
    *out = NULL;
    *out_count = 0;
    if (!(alpha > 0.0) || !isfinite(alpha))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise lights: alpha = %g must be finite and > 0", alpha);
    if (N == 0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise lights: N must be > 0");
    if (count == 0) return VBL_SUCCESS;
    for (size_t i = 0; i < count; ++i)
        if (candidates[i].material < 0 || (size_t)candidates[i].material >= material_count)
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise lights: candidates[%zu].material = %d is outside [0, %zu)",
                             i, candidates[i].material, material_count);
    if (N > count) N = count;
    vbl_vec3* p = (vbl_vec3*)malloc(count * sizeof(vbl_vec3));
    size_t* kept = (size_t*)malloc(N * sizeof(size_t));
    double* r = (double*)malloc(N * sizeof(double));
    vbl_bn_light* lights = (vbl_bn_light*)malloc(N * sizeof(vbl_bn_light));
    vbl_result rc = VBL_SUCCESS;
    if (!p || !kept || !r || !lights) {
        rc = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise lights: cannot allocate %zu candidates", count);
        goto fail;
    }
    for (size_t i = 0; i < count; ++i) p[i] = candidates[i].position;
    rc = vbl_bn_eliminate(p, count, N, elimination, kept, r, NULL);
    if (rc != VBL_SUCCESS) goto fail;
    double smallest = INFINITY;
    for (size_t k = 0; k < N; ++k)
        if (r[k] > 0.0 && r[k] < smallest) smallest = r[k];
    for (size_t k = 0; k < N; ++k) {
        const vbl_bn_candidate* c = &candidates[kept[k]];
        lights[k].position = c->position;
        lights[k].normal = c->normal;
        /* a lone candidate (N = count = 1) has no neighbour to define r_max: radius 1 */
        lights[k].radius = alpha * (r[k] > 0.0 ? r[k] : (isfinite(smallest) ? smallest : 1.0));
        lights[k].material = c->material;
        lights[k].diffuse = vbl_material_is_diffuse(&materials[c->material]);
    }
    free(p);
    free(kept);
    free(r);
    *out = lights;
    *out_count = N;
    return VBL_SUCCESS;
fail:
    free(p);
    free(kept);
    free(r);
    free(lights);
    return rc;
}
