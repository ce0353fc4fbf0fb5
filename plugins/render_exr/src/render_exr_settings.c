/* vbl_render_exr_settings: the scene facts of the header (vbl:scene_hash, vbl:media, the camera
 * matrices) and the colour-layer names --half-layers takes (vbl_render_exr.h). */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vbl_render_exr.h"

void vbl_render_exr_settings_init(vbl_render_exr_settings* s)
{
    memset(s, 0, sizeof *s);
    s->pass_first = s->pass_last = -1;
    s->compression = -1;
}

/* FNV-1a 64 of the file's bytes (offset basis 0xcbf29ce484222325, prime 0x100000001b3). */
vbl_result vbl_render_exr_hash_file(vbl_render_exr_settings* s, const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return vbl_report_error(errno == ENOENT ? VBL_ERROR_FILE_NOT_FOUND : VBL_ERROR_FILE_IO,
                                "%s: cannot open the scene file (%s)", path, strerror(errno));
    uint64_t h = 0xcbf29ce484222325ull;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        for (size_t i = 0; i < n; ++i) h = (h ^ buf[i]) * 0x100000001b3ull;
    int bad = ferror(f);
    fclose(f);
    if (bad) return vbl_report_error(VBL_ERROR_FILE_IO, "%s: cannot read the scene file", path);
    snprintf(s->scene_hash, sizeof s->scene_hash, "fnv1a64:%016llx", (unsigned long long)h);
    return VBL_SUCCESS;
}

void vbl_render_exr_set_scene(vbl_render_exr_settings* s, const vbl_scene* scene)
{
    double w2c[16], w2n[16];
    s->have_camera = vbl_scene_camera_matrices(scene, w2c, w2n) == VBL_SUCCESS;
    for (int e = 0; e < 16; ++e) {
        s->world_to_camera[e] = s->have_camera ? (float)w2c[e] : 0.0f;
        s->world_to_ndc[e] = s->have_camera ? (float)w2n[e] : 0.0f;
    }
    size_t used = 0;
    s->media[0] = 0;
    for (int i = 0; i < vbl_scene_medium_count(scene); ++i) {
        const char* path = vbl_scene_medium_path(scene, i);
        char* real = path ? realpath(path, NULL) : NULL;
        int n = snprintf(s->media + used, sizeof s->media - used, "%s%s", i ? ";" : "",
                         real ? real : (path ? path : ""));
        free(real);
        if (n < 0 || (size_t)n >= sizeof s->media - used) break;
        used += (size_t)n;
    }
}

static int vbl_render_exr_is_total(const char* p, size_t n)
{
    return (n == strlen(VBL_FILM_TOTAL_VOLUME_INDIRECT) && !strncmp(p, VBL_FILM_TOTAL_VOLUME_INDIRECT, n)) ||
           (n == strlen(VBL_FILM_TOTAL_SURFACE_INDIRECT) && !strncmp(p, VBL_FILM_TOTAL_SURFACE_INDIRECT, n));
}

int vbl_render_exr_is_colour_layer(const char* p, size_t n)
{
    if ((n == 6 && !strncmp(p, "beauty", 6)) || (n == 8 && !strncmp(p, "variance", 8))) return 1;
    if (vbl_render_exr_is_total(p, n)) return 1;
    if (n > 11 && !strncmp(p, "lightgroup_", 11)) return 1;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        const char* name = vbl_transport_class_name((vbl_transport_class)c);
        if (strlen(name) == n && !strncmp(p, name, n)) return 1;
    }
    return 0;
}

vbl_result vbl_render_exr_check_half_layers(const char* list)
{
    for (const char* p = list; p && *p;) {
        size_t n = strcspn(p, ",");
        if (!vbl_render_exr_is_colour_layer(p, n))
            return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                    "'%.*s' is not a colour layer (beauty, background, volume_direct, "
                                    "volume_from_volume, ..., volume_indirect, surface_indirect, variance; Z and "
                                    "samples are always FLOAT)",
                                    (int)n, p);
        p += n;
        if (*p == ',') ++p;
    }
    return VBL_SUCCESS;
}

vbl_render_exr_kind vbl_render_exr_layer_kind(const char* name)
{
    if (!name[0]) return VBL_RENDER_EXR_BEAUTY;
    if (vbl_render_exr_is_total(name, strlen(name))) return VBL_RENDER_EXR_TOTAL;
    if (!strncmp(name, "lightgroup_", 11)) return VBL_RENDER_EXR_GROUP;
    if (!strcmp(name, "Z")) return VBL_RENDER_EXR_Z;
    if (!strcmp(name, "samples")) return VBL_RENDER_EXR_SAMPLES;
    if (!strcmp(name, "variance")) return VBL_RENDER_EXR_VARIANCE;
    return VBL_RENDER_EXR_TRANSPORT;
}
