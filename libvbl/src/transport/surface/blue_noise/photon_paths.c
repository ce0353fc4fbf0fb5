/* Surface light paths split into the blue-noise lights' incident fields (photon_paths.h). */
#include "transport/surface/blue_noise/photon_paths.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "transport/surface/blue_noise/stop_latch.h"
#include "core/rng.h"
#include "media/medium.h"
#include "transport/common/light_emission.h"
#include "volume/transmittance.h"

typedef struct path_hits {
    vbl_bn_photon_hit* hits;
    size_t count, capacity;
    vbl_vec3 emitted;
    int failed;
} path_hits;

static void push_hit(path_hits* p, const vbl_bn_photon_hit* h)
{
    if (p->count == p->capacity) {
        size_t cap = p->capacity ? 2 * p->capacity : 4;
        vbl_bn_photon_hit* n = (vbl_bn_photon_hit*)realloc(p->hits, cap * sizeof(*n));
        if (!n) {
            p->failed = 1;
            return;
        }
        p->hits = n;
        p->capacity = cap;
    }
    p->hits[p->count++] = *h;
}

typedef struct shared {
    const vbl_scene* scene;
    const vbl_bn_photon_options* o;
    vbl_photon_source source;
} shared;

static void trace_path(const shared* sh, size_t index, path_hits* out)
{
    const vbl_scene* scene = sh->scene;
    vbl_rng rng = vbl_rng_make(sh->o->seed, VBL_BN_PHOTON_STREAM, (uint64_t)index);
    vbl_emission_sample es;
    vbl_vec3 phi;
    if (!vbl_photon_emit(&sh->source, scene, sh->o->paths, &rng, &es, &phi)) return;
    const double phi0 = vbl_v3_max_component(phi);
    out->emitted = phi;
    vbl_vec3 x = es.origin, d = es.direction;
    const vbl_extinction* ext = sh->o->extinction;
    const int media = ext && ext->count > 0;
    vbl_extinction_cursor cursor;
    if (media) vbl_extinction_cursor_init(&cursor, ext);
    vbl_medium_point mp; /* what scatters at a collision (media/medium.h) */
    for (int k = 0;; ++k) {
        vbl_surface_hit hit;
        const int on_surface = vbl_surfaces_intersect(scene->surfaces, x, d, 0.0, INFINITY, &hit);
        double t0 = 0.0, t1 = 0.0, t = 0.0;
        int collided = 0;
        if (media && vbl_extinction_ray_bounds(ext, x, d, 0.0, on_surface ? hit.t : INFINITY, &t0, &t1) && t1 > t0) {
            const vbl_segment seg = vbl_segment_make(x, d, t0, t1);
            collided = vbl_medium_free_flight(scene, ext, &cursor, &seg, sh->o->use_global_majorant, &rng, &t, &mp);
        }
        if (collided) {
            /* a medium scattering event k: not split; the next hit has k + 1 earlier events */
            if (!(mp.sigma_t > 0.0) || (sh->o->max_bounce >= 0 && k >= sh->o->max_bounce)) return;
            double u[3];
            for (int j = 0; j < 3; ++j) u[j] = vbl_rng_uniform(&rng);
            vbl_vec3 wi;
            if (!vbl_medium_scatter(&mp, d, u, &wi, NULL, &phi)) return;
            if (!vbl_photon_continues(&phi, phi0, k >= 1, &rng)) return;
            x = vbl_v3_madd(x, d, t);
            d = wi;
            continue;
        }
        if (!on_surface) return;
        vbl_vec3 wi = vbl_v3_scale(d, -1.0);
        if (sh->o->max_bounce < 0 || k <= sh->o->max_bounce) {
            vbl_bn_photon_hit h = {hit.position, hit.shading_normal, wi, phi};
            push_hit(out, &h);
            if (out->failed) return;
        }
        if (sh->o->max_bounce >= 0 && k >= sh->o->max_bounce) return;
        const vbl_material* m = &scene->materials[hit.material];
        double u0 = vbl_rng_uniform(&rng), u1 = vbl_rng_uniform(&rng), u2 = vbl_rng_uniform(&rng);
        vbl_vec3 w, f;
        double pdf = 0.0;
        if (!vbl_material_sample(m, hit.shading_normal, wi, u0, u1, u2, &w, &pdf, &f) || !(pdf > 0.0)) return;
        double cos_o = vbl_v3_dot(w, hit.shading_normal);
        if (!(cos_o > 0.0) || !(vbl_v3_dot(w, hit.geometric_normal) > 0.0)) return;
        f = vbl_material_eval(m, hit.shading_normal, w, wi); /* f(outgoing, incident) */
        phi = vbl_v3_scale(vbl_v3_mul(phi, f), cos_o / pdf);
        if (!vbl_photon_continues(&phi, phi0, k >= 1, &rng)) return; /* roulette from the third hit on */
        double eps = vbl_surfaces_ray_epsilon(scene->surfaces, hit.position);
        x = vbl_v3_madd(hit.position, hit.geometric_normal, eps);
        d = w;
    }
}

vbl_result vbl_bn_trace_photons(const vbl_scene* scene, const vbl_bn_photon_options* options,
                                vbl_bn_incident_field* field, vbl_bn_photon_stats* stats)
{
    vbl_bn_photon_options defaults = VBL_BN_PHOTON_DEFAULT;
    const vbl_bn_photon_options* o = options ? options : &defaults;
    vbl_bn_photon_stats st;
    memset(&st, 0, sizeof st);
    if (stats) *stats = st;
    if (o->size < sizeof(vbl_bn_photon_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise photons: options.size = %zu is too small", o->size);
    if (!scene->surfaces || scene->surface_count <= 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise photons: scene '%s' has no surfaces", scene->path);
    if (o->paths == 0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise photons: options.paths must be > 0");
    shared sh;
    memset(&sh, 0, sizeof sh);
    sh.scene = scene;
    sh.o = o;
    vbl_vec3 center, lo, hi;
    double radius;
    if (!vbl_surfaces_bounds(scene->surfaces, &lo, &hi) ||
        !vbl_photon_emission_sphere(scene, o->extinction && o->extinction->count > 0, &center, &radius))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "blue noise photons: scene '%s' has no surfaces", scene->path);
    const double power = vbl_photon_source_init(&sh.source, scene, center, radius);
    st.paths = o->paths;
    if (!(power > 0.0)) {
        if (stats) *stats = st;
        return VBL_SUCCESS;
    }
    const size_t chunk = o->chunk ? o->chunk : 16384;
    path_hits* ph = (path_hits*)calloc(chunk, sizeof(path_hits));
    if (!ph) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise photons: cannot allocate a chunk of %zu paths", chunk);
    vbl_result rc = VBL_SUCCESS;
    int stopped = 0; /* o->stop said stop: the chunk's remaining paths are skipped */
    for (size_t start = 0; start < o->paths && rc == VBL_SUCCESS; start += chunk) {
        size_t n = o->paths - start < chunk ? o->paths - start : chunk;
#pragma omp parallel for schedule(dynamic, 64)
        for (long long i = 0; i < (long long)n; ++i) {
            path_hits* p = &ph[i];
            p->count = 0;
            p->failed = 0;
            p->emitted = vbl_v3(0, 0, 0);
            if (vbl_bn_stop_latch(&stopped, i, o->stop, o->stop_user)) continue;
            trace_path(&sh, start + (size_t)i, p);
        }
        if (stopped) {
            rc = vbl_error(VBL_ERROR_INTERRUPTED, "blue noise photons: stopped (cancel or time limit) after %zu of %zu paths",
                           start, o->paths);
            break;
        }
        for (size_t i = 0; i < n && rc == VBL_SUCCESS; ++i) {
            if (ph[i].failed) {
                rc = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise photons: out of memory on path %zu", start + i);
                break;
            }
            st.emitted = vbl_v3_add(st.emitted, ph[i].emitted);
            size_t lost_before = field->lost_hits;
            rc = vbl_bn_split_photons(field, ph[i].hits, ph[i].count);
            st.hits += ph[i].count;
            st.lost_hits += field->lost_hits - lost_before;
        }
    }
    for (size_t i = 0; i < chunk; ++i) free(ph[i].hits);
    free(ph);
    if (stats) *stats = st;
    return rc;
}
