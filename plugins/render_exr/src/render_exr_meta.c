/* The header attributes of `vbl render -o` (docs/readme/output.md, "Metadata";
 * docs/readme/pipeline.md), in the file's order (vbl_render_exr.h). */
#include <stdio.h>
#include <string.h>

#include "vbl_render_exr.h"

static void vbl_render_exr_meta_add(vbl_render_exr_meta* m, const char* name, const char* value,
                                    vbl_exr_attribute_type type, int int_value, double double_value)
{
    if (m->count >= VBL_RENDER_EXR_MAX_ATTRS) return;
    vbl_exr_attribute* a = &m->attrs[m->count++];
    a->name = name;
    a->value = value;
    a->type = type;
    a->int_value = int_value;
    a->double_value = double_value;
}

void vbl_render_exr_meta_make(const vbl_render_exr_settings* s, const vbl_film_stats* stats,
                              const vbl_render_options* options, int passes, int first_pass, int passes_requested,
                              const char* status, double render_seconds, vbl_render_exr_meta* m)
{
    const vbl_exr_attribute_type S = VBL_EXR_ATTRIBUTE_STRING, I = VBL_EXR_ATTRIBUTE_INT, D = VBL_EXR_ATTRIBUTE_DOUBLE;
    memset(m, 0, sizeof *m);
    snprintf(m->software, sizeof m->software, "vbl %s", vbl_version_string());
    snprintf(m->seed, sizeof m->seed, "%llu", (unsigned long long)stats->seed);
    vbl_render_options_hash(options, m->options_hash, sizeof m->options_hash);
    vbl_render_exr_meta_add(m, "software", m->software, S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:version", vbl_version_string(), S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:scene", s->scene_label ? s->scene_label : "", S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:scene_hash", s->scene_hash, S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:media", s->media, S, 0, 0.0);
    if (s->has_frame) vbl_render_exr_meta_add(m, "vbl:frame", NULL, I, s->frame, 0.0);
    vbl_render_exr_meta_add(m, "vbl:method", vbl_render_method_name(stats->method), S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:preset", s->preset ? s->preset : "none", S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:status", status, S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:passes", NULL, I, passes, 0.0);
    vbl_render_exr_meta_add(m, "vbl:passes_requested", NULL, I, passes_requested, 0.0);
    vbl_render_exr_meta_add(m, "vbl:first_pass", NULL, I, first_pass, 0.0);
    if (s->pass_first >= 0) {
        snprintf(m->pass_range, sizeof m->pass_range, "%ld-%ld", s->pass_first, s->pass_last);
        vbl_render_exr_meta_add(m, "vbl:pass_range", m->pass_range, S, 0, 0.0);
    }
    vbl_render_exr_meta_add(m, "vbl:spp", NULL, I, stats->spp, 0.0);
    vbl_render_exr_meta_add(m, "vbl:light_paths", NULL, I, stats->light_paths, 0.0);
    vbl_render_exr_meta_add(m, "vbl:seed", m->seed, S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:options_hash", m->options_hash, S, 0, 0.0);
    vbl_render_exr_meta_add(m, "vbl:threads", NULL, I, stats->threads, 0.0);
    vbl_render_exr_meta_add(m, "vbl:max_bounces", NULL, I, options->max_bounces, 0.0);
    vbl_render_exr_meta_add(m, "vbl:transmittance", vbl_transmittance_estimator_name(options->transmittance), S, 0,
                            0.0);
    vbl_render_exr_meta_add(m, "vbl:render_seconds", NULL, D, 0, render_seconds);
    vbl_render_exr_meta_add(m, "vbl:alpha",
                            options->transparent
                                ? "premultiplied; A = 1 - transmittance along the camera ray; the beauty leaves out "
                                  "the background layer (transparent)"
                                : "premultiplied; A = 1 - transmittance along the camera ray (1 where a background "
                                  "layer is rendered: it is in the beauty)",
                            S, 0, 0.0);
    if (options->transparent) vbl_render_exr_meta_add(m, "vbl:transparent", NULL, I, 1, 0.0);
    if (stats->hybrid) { /* render.hybrid: the classes pt rendered, as chosen (docs/readme/hybrid.md) */
        size_t n = (size_t)snprintf(m->hybrid, sizeof m->hybrid, "pt:");
        int any = 0;
        for (int c = 0; c < VBL_CLASS_COUNT && n < sizeof m->hybrid; ++c)
            if (stats->hybrid_pt_classes & (1 << c)) {
                n += (size_t)snprintf(m->hybrid + n, sizeof m->hybrid - n, "%s%s", any ? "," : " ",
                                      vbl_transport_class_name((vbl_transport_class)c));
                any = 1;
            }
        if (n < sizeof m->hybrid)
            snprintf(m->hybrid + n, sizeof m->hybrid - n, "%s; pt_spp %d (%s)", any ? "" : " none",
                     stats->hybrid_pt_spp, stats->hybrid == VBL_HYBRID_AUTO ? "auto" : "classes");
        vbl_render_exr_meta_add(m, "vbl:hybrid", m->hybrid, S, 0, 0.0);
    }
    if (s->have_camera) {
        vbl_render_exr_meta_add(m, "worldToCamera", NULL, VBL_EXR_ATTRIBUTE_M44F, 0, 0.0);
        m->attrs[m->count - 1].m44 = s->world_to_camera;
        vbl_render_exr_meta_add(m, "worldToNDC", NULL, VBL_EXR_ATTRIBUTE_M44F, 0, 0.0);
        m->attrs[m->count - 1].m44 = s->world_to_ndc;
    }
    vbl_render_exr_meta_add(m, "vbl:scene_color_space", s->scene_space ? s->scene_space : "scene_linear", S, 0, 0.0);
    /* written by the EXR writer from write options; listed here for the identity checks */
    if (s->output_space) vbl_render_exr_meta_add(m, "oiio:ColorSpace", s->output_space, S, 0, 0.0);
}
