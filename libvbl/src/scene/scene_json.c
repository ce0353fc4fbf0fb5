/* Validated JSON reads for the scene loader (messages name the file and the field). */
#include "scene/scene_json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"

vbl_result vbl_json_fail(const vbl_json_ctx* ctx, const char* fmt, ...)
{
    char message[1536];
    va_list args;
    va_start(args, fmt);
    vsnprintf(message, sizeof message, fmt, args);
    va_end(args);
    return vbl_error(VBL_ERROR_SCENE, "%s: %s", ctx->path, message);
}

void vbl_json_field(char* out, size_t size, const char* parent, const char* key)
{
    if (!parent || !parent[0])
        snprintf(out, size, "%s", key);
    else
        snprintf(out, size, "%s.%s", parent, key);
}

vbl_result vbl_json_check_keys(const vbl_json_ctx* ctx, const cJSON* object, const char* field,
                               const char* const* allowed)
{
    for (const cJSON* child = object->child; child; child = child->next) {
        const char* key = child->string ? child->string : "";
        if (key[0] == '_') continue;
        int known = 0;
        for (const char* const* a = allowed; *a; ++a)
            if (!strcmp(*a, key)) known = 1;
        if (!known) {
            char full[512];
            vbl_json_field(full, sizeof full, field, key);
            return vbl_json_fail(ctx, "unknown key '%s'", full);
        }
    }
    return VBL_SUCCESS;
}

static const cJSON* vbl_json_get(const cJSON* parent, const char* key)
{
    return cJSON_GetObjectItemCaseSensitive(parent, key);
}

vbl_result vbl_json_object(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                           const char* key, int required, const cJSON** out)
{
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    const cJSON* item = vbl_json_get(parent, key);
    if (!item) return required ? vbl_json_fail(ctx, "%s is missing", field) : VBL_SUCCESS;
    if (!cJSON_IsObject(item)) return vbl_json_fail(ctx, "%s must be an object", field);
    *out = item;
    return VBL_SUCCESS;
}

vbl_result vbl_json_number(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                           const char* key, int required, double* out)
{
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    const cJSON* item = vbl_json_get(parent, key);
    if (!item) return required ? vbl_json_fail(ctx, "%s is missing", field) : VBL_SUCCESS;
    if (!cJSON_IsNumber(item)) return vbl_json_fail(ctx, "%s must be a number", field);
    if (!isfinite(item->valuedouble)) return vbl_json_fail(ctx, "%s must be finite", field);
    *out = item->valuedouble;
    return VBL_SUCCESS;
}

vbl_result vbl_json_int(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                        const char* key, int required, double min, double max, double* out)
{
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    const cJSON* item = vbl_json_get(parent, key);
    if (!item) return required ? vbl_json_fail(ctx, "%s is missing", field) : VBL_SUCCESS;
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble) || item->valuedouble != floor(item->valuedouble))
        return vbl_json_fail(ctx, "%s must be an integer", field);
    double v = item->valuedouble;
    if (v < min || v > max) return vbl_json_fail(ctx, "%s = %.17g is outside [%.17g, %.17g]", field, v, min, max);
    *out = v;
    return VBL_SUCCESS;
}

vbl_result vbl_json_string(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                           const char* key, int required, const char** out)
{
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    const cJSON* item = vbl_json_get(parent, key);
    if (!item) return required ? vbl_json_fail(ctx, "%s is missing", field) : VBL_SUCCESS;
    if (!cJSON_IsString(item) || !item->valuestring) return vbl_json_fail(ctx, "%s must be a string", field);
    *out = item->valuestring;
    return VBL_SUCCESS;
}

vbl_result vbl_json_vec3(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                         const char* key, int required, vbl_vec3* out)
{
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    const cJSON* item = vbl_json_get(parent, key);
    if (!item) return required ? vbl_json_fail(ctx, "%s is missing", field) : VBL_SUCCESS;
    double v[3];
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return vbl_json_fail(ctx, "%s must be an array of 3 numbers", field);
    for (int i = 0; i < 3; ++i) {
        const cJSON* c = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
            return vbl_json_fail(ctx, "%s[%d] must be a finite number", field, i);
        v[i] = c->valuedouble;
    }
    *out = vbl_v3(v[0], v[1], v[2]);
    return VBL_SUCCESS;
}

vbl_result vbl_json_rgb(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                        const char* key, int required, double min, double max, vbl_vec3* out)
{
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    const cJSON* item = vbl_json_get(parent, key);
    if (!item) return required ? vbl_json_fail(ctx, "%s is missing", field) : VBL_SUCCESS;
    double v[3];
    if (cJSON_IsNumber(item)) {
        if (!isfinite(item->valuedouble)) return vbl_json_fail(ctx, "%s must be finite", field);
        v[0] = v[1] = v[2] = item->valuedouble;
        if (v[0] < min || v[0] > max)
            return vbl_json_fail(ctx, "%s = %g is outside [%g, %g]", field, v[0], min, max);
    } else {
        if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
            return vbl_json_fail(ctx, "%s must be a number or an array of 3 numbers", field);
        for (int i = 0; i < 3; ++i) {
            const cJSON* c = cJSON_GetArrayItem(item, i);
            if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
                return vbl_json_fail(ctx, "%s[%d] must be a finite number", field, i);
            v[i] = c->valuedouble;
            if (v[i] < min || v[i] > max)
                return vbl_json_fail(ctx, "%s[%d] = %g is outside [%g, %g]", field, i, v[i], min, max);
        }
    }
    *out = vbl_v3(v[0], v[1], v[2]);
    return VBL_SUCCESS;
}
