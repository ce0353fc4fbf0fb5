/* The store and kernel interface of the virtual-light estimator (virtual_lights.h), private to
 * transport/virtual_lights/: virtual_lights.c owns the common parts, vpl.c / vrl.c /
 * virtual_beam_lights.c the kernels (point, ray, beam). */
#ifndef VBL_TRANSPORT_VIRTUAL_LIGHTS_KERNEL_H
#define VBL_TRANSPORT_VIRTUAL_LIGHTS_KERNEL_H

#include "transport/common/photon_trace.h"
#include "transport/surface/surface_gather.h"
#include "transport/virtual_lights/virtual_beam_lights.h"
#include "transport/virtual_lights/virtual_lights.h"
#include "transport/virtual_lights/vpl.h"
#include "transport/virtual_lights/vrl.h"
#include "transport/virtual_lights/vrl_tree.h"

struct vbl_photon_beam_gather;
struct vbl_step_pdf;

/* One pass's store; the kernel's begin / after_trace fill what is theirs. */
typedef struct vbl_vl_store {
    const vbl_vl_kernel* kernel;
    vbl_photon_store photons;
    vbl_photon_settings trace;          /* the photon trace (vbl_photon_trace_with_surfaces) */
    vbl_surface_gather_settings gather; /* surfaces (surface_gather.h) */
    vbl_vrl_tree tree;                  /* select > 0: the pass's light tree (vrl_tree.h) */
    int select;                         /* K lights per camera sample from the tree; 0: every light */
    int samples;                        /* S draws per light / camera-segment pair */
    double g_camera;                    /* HG g the samplers use at camera points (any value is unbiased) */
    double camera_rr;                   /* roulette threshold of the camera cache (0: the tracker's) */
    int camera_mis;                     /* ray: MIS with the camera-transmittance technique */
    double rr_distance;                 /* distance roulette radius, world units (segments); 0: off */
    double rr_min_probability;          /* its survival floor */
    vbl_tracking_settings connect;      /* the connecting segments' transmittance */
    int beams_direct;                   /* beam: volume_direct by bounce-0 photon beams */
    struct vbl_photon_beam_gather* beams;
    vbl_vpl_settings point;             /* point kernel */
    vbl_vrl_settings ray;               /* ray kernel */
    struct {                            /* beam kernel (virtual_beam_lights.h) */
        vbl_beam_light_settings settings;
        double radius;         /* R_p of this pass (world units): the cap of every VSL's radius */
        double radius_mfp;     /* s_p x settings.radius_mfp (0: off) */
        double sampler_radius; /* the pair sampler's R: min(radius, radius_mfp / majorant) */
        double thin_sin;       /* VSLs with R <= thin_sin w take the midpoint kernel */
        double beam_radius;    /* the bounce-0 photon beams' width */
    } beam;
} vbl_vl_store;

/* One camera sample's gather over the lights: the store, the camera segment with its cache, and
 * the estimate's accumulator (also the light tree's visitor). */
typedef struct vbl_vl_gather {
    const vbl_render_context* ctx;
    const vbl_vl_store* s;
    vbl_thread_state* ts;
    const vbl_vl_camera* cam;
    const struct vbl_step_pdf* camera; /* camera_mis: the camera technique's u density, or NULL */
    vbl_rng* rng;
    vbl_vec3* acc;
} vbl_vl_gather;

/* The trace settings of the segment kernels (ray, beam): store the VRLs (long ones split as asked),
 * each with a 16-entry transmittance cache of the render's kind (delta if cached-delta, else ratio). */
static inline void vbl_vl_trace_segments(const vbl_render_context* ctx, vbl_vl_store* s, int long_vrls)
{
    s->trace.store_vrls = 1;
    s->trace.long_vrls = long_vrls;
    s->trace.cache_kind = ctx->options.transmittance == VBL_TRANSMITTANCE_CACHED_DELTA ? VBL_TRANSMITTANCE_CACHED_DELTA
                                                                                     : VBL_TRANSMITTANCE_CACHED_RATIO;
    s->trace.cache_entries = 16;
}

struct vbl_vl_kernel {
    const char* name;
    int points;            /* 1: the lights are the store's VPLs; 0: its VRLs (segments, tree pieces) */
    int scatter_offset;    /* a light of bounce k carries light that scattered k + offset times */
    int weight_per_sample; /* 1: the gather's weight carries 1 / samples; 0: the kernel divides by it */
    /* Checks the settings and fills the store's fields the trace needs (trace, samples, select, ...). */
    vbl_result (*begin)(const vbl_render_context* ctx, const void* settings, vbl_vl_store* s);
    /* After the trace: radii, the surface gather settings, beams (may be NULL). */
    vbl_result (*after_trace)(const vbl_render_context* ctx, vbl_vl_store* s);
    /* Adds light `light`'s volume_from_volume estimate over its part v in [v0, v1] (segments; whole
     * light: [0, length]) times `weight` to *g->acc. */
    void (*estimate)(const vbl_vl_gather* g, size_t light, double v0, double v1, double weight);
};

#endif
