/* render.hybrid: the per-class combination of a virtual-light method with pt (hybrid.h). */
#include "render/hybrid.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "transport/path_tracing/pt.h"

typedef struct vbl_hybrid_store {
    const vbl_hybrid_plan* plan;
    vbl_render_context method_ctx; /* skip_classes = pt's classes */
    vbl_render_context pt_ctx;     /* skip_classes = the method's; pt.sampler independent */
    void* method_store;
    int run_method, run_pt;
} vbl_hybrid_store;

void vbl_hybrid_combine(const vbl_sample_value* method, const vbl_sample_value* pt_sum, int pt_count,
                        unsigned pt_classes, vbl_sample_value* out)
{
    const double w = pt_count > 0 ? 1.0 / pt_count : 0.0;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        if (pt_classes & (1u << (unsigned)c)) out->L[c] = vbl_v3_scale(pt_sum->L[c], w);
        else out->L[c] = method->L[c];
    }
}

void vbl_hybrid_describe(unsigned pt_classes, int pt_spp, int automatic, char* out, size_t size)
{
    size_t n = 0;
    int any = 0;
    if (!out || size == 0) return;
    n += (size_t)snprintf(out + n, n < size ? size - n : 0, "pt: ");
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        if (!(pt_classes & (1u << (unsigned)c))) continue;
        n += (size_t)snprintf(out + n, n < size ? size - n : 0, "%s%s", any ? "," : "", vbl_transport_class_name(c));
        any = 1;
    }
    if (!any) n += (size_t)snprintf(out + n, n < size ? size - n : 0, "none");
    snprintf(out + n, n < size ? size - n : 0, "; pt_spp %d (%s)", pt_spp, automatic ? "auto" : "classes");
}

vbl_result vbl_hybrid_plan_make(const vbl_render_context* ctx, const vbl_estimator* base, vbl_hybrid_plan* out)
{
    memset(out, 0, sizeof *out);
    out->base = base;
    const vbl_render_method m = ctx->options.method;
    if (m == VBL_RENDER_PT || !base || !base->pass_begin)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "%s: hybrid = %s combines pt with a virtual-light method (vpl, vrl, vbl, beams), not '%s'",
                         ctx->scene->path, ctx->options.hybrid == VBL_HYBRID_AUTO ? "auto" : "classes",
                         base ? base->name : vbl_render_method_name(m));
    if (ctx->options.hybrid == VBL_HYBRID_AUTO) {
        out->automatic = 1;
        return vbl_hybrid_pilot(ctx, base, out);
    }
    out->pt_classes = (unsigned)ctx->options.hybrid_pt_classes & VBL_HYBRID_ALL_CLASSES;
    out->pt_spp = ctx->options.hybrid_pt_spp;
    return VBL_SUCCESS;
}

static vbl_result vbl_hybrid_pass_begin(const vbl_render_context* ctx, void** store)
{
    *store = NULL;
    const vbl_hybrid_plan* plan = ctx->hybrid;
    if (!plan || !plan->base)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: hybrid estimator without a plan", ctx->scene->path);
    vbl_hybrid_store* h = calloc(1, sizeof *h);
    if (!h) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (hybrid store)", ctx->scene->path);
    h->plan = plan;
    h->method_ctx = *ctx;
    h->method_ctx.skip_classes = plan->pt_classes;
    h->pt_ctx = *ctx;
    h->pt_ctx.skip_classes = VBL_HYBRID_ALL_CLASSES & ~plan->pt_classes;
    h->pt_ctx.options.pt.sampler = VBL_PT_SAMPLER_INDEPENDENT; /* the pixel's Sobol index is the method's */
    h->run_method = plan->pt_classes != VBL_HYBRID_ALL_CLASSES;
    h->run_pt = plan->pt_classes != 0 && plan->pt_spp > 0;
    if (h->run_method && plan->base->pass_begin) {
        vbl_result r = plan->base->pass_begin(&h->method_ctx, &h->method_store);
        if (r) {
            free(h);
            return r;
        }
    }
    *store = h;
    return VBL_SUCCESS;
}

static void vbl_hybrid_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                                     const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out)
{
    (void)ctx;
    const vbl_hybrid_store* h = store;
    vbl_sample_value method, pt_sum;
    memset(&method, 0, sizeof method);
    memset(&pt_sum, 0, sizeof pt_sum);
    if (h->run_method) h->plan->base->camera_sample(&h->method_ctx, h->method_store, ts, sample, rng, &method);
    int n = 0;
    if (h->run_pt) {
        for (; n < h->plan->pt_spp; ++n) {
            vbl_sample_value v;
            memset(&v, 0, sizeof v);
            vbl_pt_camera_sample(&h->pt_ctx, NULL, ts, sample, rng, &v);
            for (int c = 0; c < VBL_CLASS_COUNT; ++c) pt_sum.L[c] = vbl_v3_add(pt_sum.L[c], v.L[c]);
        }
    }
    vbl_hybrid_combine(&method, &pt_sum, n, h->plan->pt_classes, out);
}

static void vbl_hybrid_pass_end(const vbl_render_context* ctx, void* store)
{
    vbl_hybrid_store* h = store;
    if (!h) return;
    if (h->run_method && h->plan->base->pass_end) h->plan->base->pass_end(&h->method_ctx, h->method_store);
    (void)ctx;
    free(h);
}

/* correlated: the method's samples of a pass share its light store */
const vbl_estimator vbl_estimator_hybrid = {"hybrid", 1, vbl_hybrid_pass_begin, vbl_hybrid_camera_sample,
                                            vbl_hybrid_pass_end, NULL};
