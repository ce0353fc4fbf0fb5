/* Frame substitution in media[i].vdb paths (scene_frame.h). */
#include "scene/scene_frame.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"

/* Length of the "%[0][width]d" conversion at p (p[0] == '%'), or 0 if it is not one. */
static size_t vbl_frame_conversion(const char* p, int* width, int* zero)
{
    size_t i = 1;
    *zero = 0;
    *width = 0;
    if (p[i] == '0') {
        *zero = 1;
        ++i;
    }
    while (p[i] >= '0' && p[i] <= '9' && *width < 100) *width = *width * 10 + (p[i++] - '0');
    return p[i] == 'd' ? i + 1 : 0;
}

int vbl_frame_path_has_pattern(const char* path)
{
    if (!path) return 0;
    for (const char* p = path; *p; ++p) {
        int width, zero;
        if (*p == '#') return 1;
        if (*p == '%' && vbl_frame_conversion(p, &width, &zero)) return 1;
        if (*p == '%' && p[1] == '%') ++p;
    }
    return 0;
}

int vbl_frame_path_format(const char* pattern, int frame, char* out, size_t size)
{
    size_t n = 0;
    for (const char* p = pattern; *p;) {
        char piece[128];
        size_t len = 0, used = 1;
        int width = 0, zero = 0;
        if (*p == '#') {
            while (p[width] == '#') ++width;
            used = (size_t)width;
            len = (size_t)snprintf(piece, sizeof piece, "%0*d", width, frame);
        } else if (*p == '%' && p[1] == '%') {
            used = 2;
            piece[0] = '%';
            len = 1;
        } else if (*p == '%') {
            used = vbl_frame_conversion(p, &width, &zero);
            if (!used) return -1;
            len = (size_t)(zero ? snprintf(piece, sizeof piece, "%0*d", width, frame)
                                : snprintf(piece, sizeof piece, "%*d", width, frame));
        } else {
            piece[0] = *p;
            len = 1;
        }
        if (len >= sizeof piece || n + len + 1 > size) return -1;
        memcpy(out + n, piece, len);
        n += len;
        p += used;
    }
    if (n + 1 > size) return -1;
    out[n] = 0;
    return 0;
}

vbl_result vbl_scene_frame_vdb(const char* scene_path, const char* field, const cJSON* medium, const char* dir,
                               const vbl_scene_load_options* options, const char** vdb_override, char* buf,
                               size_t size)
{
    const char* pattern = *vdb_override;
    int relative_to_scene = 0;
    if (!pattern) {
        const cJSON* vdb = cJSON_IsObject(medium) ? cJSON_GetObjectItemCaseSensitive(medium, "vdb") : NULL;
        if (!cJSON_IsString(vdb)) return VBL_SUCCESS; /* the loader reports a missing/odd vdb */
        pattern = vdb->valuestring;
        relative_to_scene = pattern[0] != '/';
    }
    if (!vbl_frame_path_has_pattern(pattern)) return VBL_SUCCESS;
    int has_frame = options && options->size >= offsetof(vbl_scene_load_options, use_frame) + sizeof(int) &&
                    options->use_frame;
    if (!has_frame)
        return vbl_error(VBL_ERROR_SCENE,
                         "%s: %s.vdb = '%s' is a frame sequence pattern but no frame was given (vbl render --frames; "
                         "vbl_scene_load_options.use_frame/frame)",
                         scene_path, field, pattern);
    char framed[4096];
    if (vbl_frame_path_format(pattern, options->frame, framed, sizeof framed))
        return vbl_error(VBL_ERROR_SCENE, "%s: %s.vdb = '%s': bad frame pattern (use #### or %%04d)", scene_path,
                         field, pattern);
    int n = relative_to_scene ? snprintf(buf, size, "%s%s", dir, framed) : snprintf(buf, size, "%s", framed);
    if (n < 0 || (size_t)n >= size)
        return vbl_error(VBL_ERROR_SCENE, "%s: %s.vdb = '%s': path too long for frame %d", scene_path, field,
                         pattern, options->frame);
    FILE* probe = fopen(buf, "rb");
    if (!probe)
        return vbl_error(VBL_ERROR_FILE_NOT_FOUND, "%s: %s.vdb = '%s': frame %d: cannot open '%s' (%s)", scene_path,
                         field, pattern, options->frame, buf, strerror(errno));
    fclose(probe);
    *vdb_override = buf;
    return VBL_SUCCESS;
}
