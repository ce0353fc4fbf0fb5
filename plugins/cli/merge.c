/* Identity checks of partial renders (merge.h). */
#include "merge.h"

#include <stdio.h>
#include <string.h>

const char* const vbl_merge_identity_keys[VBL_MERGE_IDENTITY_COUNT] = {
    "vbl:scene_hash", "vbl:method", "vbl:seed",  "vbl:spp",        "vbl:light_paths",
    "vbl:options_hash", "vbl:frame", "vbl:media", "oiio:ColorSpace"};

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
