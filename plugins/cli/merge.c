/* Pass-weighted combination of partial renders (merge.h). */
#include "merge.h"

#include <stdio.h>
#include <string.h>

const char* const vbl_merge_transport_order[VBL_MERGE_TRANSPORT_COUNT] = {
    "emission",          "surface_direct",      "volume_direct",     "surface_from_surface",
    "surface_from_volume", "volume_from_surface", "volume_from_volume"};

const char* const vbl_merge_identity_keys[VBL_MERGE_IDENTITY_COUNT] = {
    "vbl:scene_hash", "vbl:method", "vbl:seed",  "vbl:spp",        "vbl:light_paths",
    "vbl:options_hash", "vbl:frame", "vbl:media", "oiio:ColorSpace"};

vbl_merge_kind vbl_merge_kind_of(const char* channel)
{
    if (!strcmp(channel, "R") || !strcmp(channel, "G") || !strcmp(channel, "B")) return VBL_MERGE_BEAUTY;
    if (!strcmp(channel, "Z")) return VBL_MERGE_DEPTH;
    if (!strncmp(channel, "samples.", 8)) return VBL_MERGE_SUM;
    if (!strncmp(channel, "variance.", 9)) return VBL_MERGE_VARIANCE;
    return VBL_MERGE_MEAN;
}

void vbl_merge_channel(vbl_merge_kind kind, int count, const int* passes, const vbl_merge_view* in,
                       const vbl_merge_view* alpha, size_t n, float* out, size_t out_stride)
{
    double total = 0.0;
    for (int k = 0; k < count; ++k) total += passes[k];
    for (size_t i = 0; i < n; ++i) {
        double sum = 0.0, weight_sum = 0.0;
        for (int k = 0; k < count; ++k) {
            double x = in[k].data[i * in[k].stride];
            double w = total > 0.0 ? passes[k] / total : 0.0;
            switch (kind) {
            case VBL_MERGE_SUM: sum += x; break;
            case VBL_MERGE_VARIANCE: sum += w * w * x; break;
            case VBL_MERGE_DEPTH: {
                /* Z = 0: no collision in that input's samples, it carries no depth */
                double a = alpha && alpha[k].data ? alpha[k].data[i * alpha[k].stride] : 1.0;
                double wa = x > 0.0 ? passes[k] * (a > 0.0 ? a : 0.0) : 0.0;
                sum += wa * x;
                weight_sum += wa;
                break;
            }
            default: sum += w * x; break;
            }
        }
        if (kind == VBL_MERGE_DEPTH) {
            if (weight_sum > 0.0) {
                sum /= weight_sum;
            } else { /* no input saw a collision: pass weights (all values are 0 then) */
                sum = 0.0;
                for (int k = 0; k < count; ++k)
                    sum += (total > 0.0 ? passes[k] / total : 0.0) * in[k].data[i * in[k].stride];
            }
        }
        out[i * out_stride] = (float)sum;
    }
}

void vbl_merge_resum_beauty(const vbl_merge_view transport[VBL_MERGE_TRANSPORT_COUNT][3], size_t n, float* beauty,
                            size_t stride)
{
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            float sum = 0.0f;
            for (int c = 0; c < VBL_MERGE_TRANSPORT_COUNT; ++c)
                if (transport[c][k].data) sum += transport[c][k].data[i * transport[c][k].stride];
            beauty[i * stride + (size_t)k] = sum;
        }
}

void vbl_merge_identity_from_image(const vbl_exr_image* image, vbl_merge_identity* out)
{
    memset(out, 0, sizeof *out);
    out->width = vbl_exr_image_width(image);
    out->height = vbl_exr_image_height(image);
    for (int k = 0; k < VBL_MERGE_IDENTITY_COUNT; ++k) {
        const char* v = vbl_exr_image_attribute(image, vbl_merge_identity_keys[k], NULL);
        if (!v) continue;
        out->has[k] = 1;
        snprintf(out->values[k], sizeof out->values[k], "%s", v);
    }
}

void vbl_merge_identity_from_attributes(const vbl_exr_attribute* attrs, int count, int width, int height,
                                        vbl_merge_identity* out)
{
    memset(out, 0, sizeof *out);
    out->width = width;
    out->height = height;
    for (int k = 0; k < VBL_MERGE_IDENTITY_COUNT; ++k)
        for (int i = 0; i < count; ++i) {
            if (strcmp(attrs[i].name, vbl_merge_identity_keys[k])) continue;
            out->has[k] = 1;
            if (attrs[i].type == VBL_EXR_ATTRIBUTE_INT)
                snprintf(out->values[k], sizeof out->values[k], "%d", attrs[i].int_value);
            else if (attrs[i].type == VBL_EXR_ATTRIBUTE_STRING)
                snprintf(out->values[k], sizeof out->values[k], "%s", attrs[i].value ? attrs[i].value : "");
            else
                snprintf(out->values[k], sizeof out->values[k], "%.17g", attrs[i].double_value);
        }
}

int vbl_merge_identity_droppable(int key)
{
    /* oiiotool rewrites EXRs without oiio:ColorSpace (it keeps the colour space in its own state);
     * a value that differs is still refused. */
    return key >= 0 && key < VBL_MERGE_IDENTITY_COUNT && !strcmp(vbl_merge_identity_keys[key], "oiio:ColorSpace");
}

int vbl_merge_identity_compare(const vbl_merge_identity* a, const char* path_a, const vbl_merge_identity* b,
                               const char* path_b, char* msg, size_t size)
{
    if (a->width != b->width || a->height != b->height) {
        snprintf(msg, size, "%s: resolution %dx%d but %s is %dx%d", path_b, b->width, b->height, path_a, a->width,
                 a->height);
        return 1;
    }
    for (int k = 0; k < VBL_MERGE_IDENTITY_COUNT; ++k) {
        if (a->has[k] == b->has[k] && (!a->has[k] || !strcmp(a->values[k], b->values[k]))) continue;
        if (vbl_merge_identity_droppable(k) && (!a->has[k] || !b->has[k])) continue;
        /* OpenImageIO drops empty string attributes (vbl:media = "" of a scene without media) */
        if (!strcmp(a->has[k] ? a->values[k] : "", b->has[k] ? b->values[k] : "")) continue;
        snprintf(msg, size, "%s: %s = %s%s%s but %s has %s%s%s", path_b, vbl_merge_identity_keys[k],
                 b->has[k] ? "\"" : "", b->has[k] ? b->values[k] : "(none)", b->has[k] ? "\"" : "", path_a,
                 a->has[k] ? "\"" : "", a->has[k] ? a->values[k] : "(none)", a->has[k] ? "\"" : "");
        return 1;
    }
    return 0;
}
