/* pt's estimator for chosen classes of a camera sample (pt_camera_classes.h). */
#include "transport/path_tracing/pt_camera_classes.h"

#include <string.h>

#include "transport/path_tracing/pt.h"
#include "transport/path_tracing/pt_camera_split.h"

/* The classes of `classes` pt traces for in this render (none: no pt path at all). */
static unsigned vbl_pt_camera_classes_keep(const vbl_render_context* ctx, unsigned classes)
{
    const unsigned all = (1u << VBL_CLASS_COUNT) - 1u;
    unsigned keep = classes & ~ctx->skip_classes & all;
    /* classes no light can reach in this scene: no path for them */
    if (!ctx->scene->has_visible_lights) keep &= ~(1u << VBL_CLASS_EMISSION);
    if (!ctx->scene->has_emission) keep &= ~(1u << VBL_CLASS_VOLUME_EMISSION);
    if (ctx->options.max_bounces == 0) keep &= ~(1u << VBL_CLASS_VOLUME_DIRECT);
    return keep;
}

int vbl_pt_camera_classes_aovs(const vbl_render_context* ctx, unsigned classes)
{
    return vbl_pt_camera_classes_keep(ctx, classes) != 0 && vbl_pt_camera_split_active(ctx);
}

void vbl_pt_camera_classes(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_camera_sample* sample,
                           unsigned classes, vbl_rng* rng, vbl_sample_value* out)
{
    const unsigned all = (1u << VBL_CLASS_COUNT) - 1u;
    const unsigned keep = vbl_pt_camera_classes_keep(ctx, classes);
    if (!keep) return;
    vbl_render_context pt_ctx = *ctx;
    pt_ctx.skip_classes = all & ~keep;
    /* every class kept ends at the first vertex, so the skipped classes stop the path there: with
     * max_bounces >= 1 the path runs unlimited so that vertex 1 traces its phase-sampled
     * continuation, the other half of the NEE / phase MIS of quad and environment lights (pt at
     * its max_bounces vertex keeps the NEE's MIS weight without it) */
    if (pt_ctx.options.max_bounces >= 1) pt_ctx.options.max_bounces = -1;
    vbl_sample_value v;
    memset(&v, 0, sizeof v);
    vbl_pt_camera_sample(&pt_ctx, NULL, ts, sample, rng, &v);
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) /* what pt adds to a skipped class anyway is dropped */
        if (keep & (1u << (unsigned)c)) out->L[c] = vbl_v3_add(out->L[c], v.L[c]);
    out->aovs = v.aovs;
}
