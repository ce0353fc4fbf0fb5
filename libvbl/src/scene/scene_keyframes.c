/* Per-frame values (scene_keyframes.h). */
#include "scene/scene_keyframes.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>

int vbl_keyframes_find(const vbl_json_ctx* ctx, const cJSON* keys, const char* field, const char* key, int frame,
                       const cJSON** below, const cJSON** above, double* weight)
{
    long fb = LONG_MIN, fa = LONG_MAX;
    *below = *above = NULL;
    for (const cJSON* k = keys ? keys->child : NULL; k; k = k->next) {
        char* end = NULL;
        errno = 0;
        long f = k->string ? strtol(k->string, &end, 10) : 0;
        if (!k->string || !k->string[0] || *end || errno || f < INT_MIN || f > INT_MAX) {
            vbl_json_fail(ctx, "%s: key \"%s\" is not a frame number", field, k->string ? k->string : "");
            return -1;
        }
        const cJSON* v = key ? cJSON_GetObjectItemCaseSensitive(k, key) : k;
        if (!v) continue;
        if (f <= frame && f > fb) fb = f, *below = v;
        if (f >= frame && f < fa) fa = f, *above = v;
    }
    if (!*below && !*above) return 0;
    if (!*below) *below = *above, fb = fa;
    if (!*above) *above = *below, fa = fb;
    *weight = fa > fb ? (double)(frame - fb) / (double)(fa - fb) : 0.0;
    return 1;
}

vbl_result vbl_keyframes_number(const vbl_json_ctx* ctx, const cJSON* keys, const char* field, const char* key,
                                int frame, double* out)
{
    const cJSON *b = NULL, *a = NULL;
    double w = 0.0;
    int found = vbl_keyframes_find(ctx, keys, field, key, frame, &b, &a, &w);
    if (found < 0) return VBL_ERROR_SCENE;
    if (!found) return VBL_SUCCESS;
    if (!cJSON_IsNumber(b) || !cJSON_IsNumber(a))
        return vbl_json_fail(ctx, "%s: every %s must be a number", field, key);
    *out = (1.0 - w) * b->valuedouble + w * a->valuedouble;
    return VBL_SUCCESS;
}

vbl_result vbl_keyframes_vec3(const vbl_json_ctx* ctx, const cJSON* keys, const char* field, const char* key,
                              int frame, vbl_vec3* out)
{
    const cJSON *b = NULL, *a = NULL;
    double w = 0.0;
    int found = vbl_keyframes_find(ctx, keys, field, key, frame, &b, &a, &w);
    if (found < 0) return VBL_ERROR_SCENE;
    if (!found) return VBL_SUCCESS;
    double v[2][3];
    const cJSON* ends[2] = {b, a};
    for (int e = 0; e < 2; ++e) {
        if (!cJSON_IsArray(ends[e]) || cJSON_GetArraySize(ends[e]) != 3)
            return vbl_json_fail(ctx, "%s: every %s must be an array of 3 numbers", field, key);
        for (int i = 0; i < 3; ++i) {
            const cJSON* c = cJSON_GetArrayItem(ends[e], i);
            if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
                return vbl_json_fail(ctx, "%s: every %s must be an array of 3 finite numbers", field, key);
            v[e][i] = c->valuedouble;
        }
    }
    *out = vbl_v3((1.0 - w) * v[0][0] + w * v[1][0], (1.0 - w) * v[0][1] + w * v[1][1],
                  (1.0 - w) * v[0][2] + w * v[1][2]);
    return VBL_SUCCESS;
}
