/* pt's estimator for chosen classes of a camera sample (pt_camera_classes.h). */
#include "transport/path_tracing/pt_camera_classes.h"

#include <string.h>

#include "transport/path_tracing/pt.h"

void vbl_pt_camera_classes(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_camera_sample* sample,
                           unsigned classes, vbl_rng* rng, vbl_sample_value* out)
{
    const unsigned all = (1u << VBL_CLASS_COUNT) - 1u;
    const unsigned keep = classes & ~ctx->skip_classes & all;
    if (!keep) return;
    vbl_render_context pt_ctx = *ctx;
    pt_ctx.skip_classes = all & ~keep;
    vbl_sample_value v;
    memset(&v, 0, sizeof v);
    vbl_pt_camera_sample(&pt_ctx, NULL, ts, sample, rng, &v);
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) /* what pt adds to a skipped class anyway is dropped */
        if (keep & (1u << (unsigned)c)) out->L[c] = vbl_v3_add(out->L[c], v.L[c]);
}
