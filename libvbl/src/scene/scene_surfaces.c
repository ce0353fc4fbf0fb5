/* Scene surfaces: the JSON "surfaces" array and the programmatic vbl_scene_add_mesh. */
#include "scene/scene_surfaces.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "geometry/mesh_load.h"
#include "geometry/subdivide.h"
#include "scene/scene_build.h"

vbl_result vbl_scene_material_check(const vbl_material* m, const char* prefix)
{
    char why[512];
    if (vbl_material_validate(m, why, sizeof why)) return VBL_SUCCESS;
    return vbl_error(VBL_ERROR_SCENE, "%s.%s", prefix, why);
}

void vbl_scene_free_surfaces(vbl_scene* scene)
{
    vbl_surfaces_release(scene->surfaces);
    free(scene->materials);
    scene->surfaces = NULL;
    scene->materials = NULL;
    scene->surface_count = 0;
    scene->has_surfaces = 0;
}

vbl_result vbl_scene_add_mesh_data(vbl_scene* scene, const vbl_mesh_data* mesh, const vbl_material* material,
                                   const vbl_affine* to_scene, const char* what)
{
    if (!scene || !mesh || !material) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_add_mesh: NULL argument");
    char prefix[1400];
    snprintf(prefix, sizeof prefix, "%s.material", what);
    vbl_result r = vbl_scene_material_check(material, prefix);
    if (r) return r;
    if (!scene->surfaces && (r = vbl_surfaces_create(scene->path, &scene->surfaces))) return r;
    vbl_material* mats = realloc(scene->materials, (size_t)(scene->surface_count + 1) * sizeof *mats);
    if (!mats) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
    scene->materials = mats;
    size_t dropped = 0;
    if ((r = vbl_surfaces_add_mesh(scene->surfaces, mesh, scene->surface_count, to_scene, what, &dropped))) return r;
    mats[scene->surface_count++] = *material;
    scene->has_surfaces = 1;
    scene->dropped_triangles += dropped;
    return VBL_SUCCESS;
}

vbl_result vbl_scene_add_mesh(vbl_scene* scene, const double* positions, size_t vertex_count, const unsigned* indices,
                              size_t triangle_count, const vbl_material* material, const vbl_affine* to_scene)
{
    if (!scene || !positions || !indices)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_add_mesh: NULL argument");
    vbl_mesh_data mesh = {(double*)positions, NULL, vertex_count, (unsigned*)indices, triangle_count};
    char what[1100];
    snprintf(what, sizeof what, "%s: surfaces[%d]", scene->path, scene->surface_count);
    return vbl_scene_add_mesh_data(scene, &mesh, material, to_scene, what);
}

static vbl_result vbl_parse_matrix(const vbl_json_ctx* ctx, const cJSON* item, const char* field, vbl_affine* out)
{
    double m[4][4];
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 4)
        return vbl_json_fail(ctx, "%s must be a 4x4 array of rows", field);
    for (int i = 0; i < 4; ++i) {
        const cJSON* row = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != 4)
            return vbl_json_fail(ctx, "%s[%d] must be an array of 4 numbers", field, i);
        for (int j = 0; j < 4; ++j) {
            const cJSON* c = cJSON_GetArrayItem(row, j);
            if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
                return vbl_json_fail(ctx, "%s[%d][%d] must be a finite number", field, i, j);
            m[i][j] = c->valuedouble;
        }
    }
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0)
        return vbl_json_fail(ctx, "%s: the last row must be [0, 0, 0, 1] (affine maps only)", field);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) out->m[i][j] = m[i][j];
    vbl_affine inv;
    if (!vbl_affine_invert(out, &inv)) return vbl_json_fail(ctx, "%s is singular", field);
    return VBL_SUCCESS;
}

static vbl_result vbl_parse_material(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                                     vbl_surface_color_fn color, const void* colors, vbl_material* m)
{
    static const char* const lambert_keys[] = {"type", "albedo", NULL};
    static const char* const phong_keys[] = {"type", "albedo", "specular", "exponent", NULL};
    static const char* const ggx_keys[] = {"type", "albedo", "specular", "roughness", NULL};
    char field[256];
    vbl_json_field(field, sizeof field, parent_field, "material");
    const cJSON* obj = NULL;
    vbl_result r;
    memset(m, 0, sizeof *m);
    m->albedo = vbl_v3(0.8, 0.8, 0.8);
    if ((r = vbl_json_object(ctx, parent, parent_field, "material", 0, &obj))) return r;
    if (!obj) return VBL_SUCCESS; /* default: Lambert, albedo 0.8 */
    const char* type = "lambert";
    if ((r = vbl_json_string(ctx, obj, field, "type", 0, &type))) return r;
    const char* const* keys;
    if (!strcmp(type, "lambert")) {
        m->type = VBL_MATERIAL_LAMBERT;
        keys = lambert_keys;
    } else if (!strcmp(type, "phong")) {
        m->type = VBL_MATERIAL_PHONG;
        m->albedo = vbl_v3(0.5, 0.5, 0.5);
        m->specular = vbl_v3(0.3, 0.3, 0.3);
        m->exponent = 60.0;
        keys = phong_keys;
    } else if (!strcmp(type, "ggx")) {
        m->type = VBL_MATERIAL_GGX;
        m->albedo = vbl_v3(0.5, 0.5, 0.5);
        m->specular = vbl_v3(0.04, 0.04, 0.04);
        m->roughness = 0.3;
        keys = ggx_keys;
    } else {
        return vbl_json_fail(ctx, "%s.type = \"%s\" is not one of lambert, phong, ggx", field, type);
    }
    if ((r = vbl_json_check_keys(ctx, obj, field, keys))) return r;
    if ((r = color(ctx, colors, obj, field, "albedo", 0.0, 1.0, &m->albedo))) return r;
    if (m->type != VBL_MATERIAL_LAMBERT && (r = color(ctx, colors, obj, field, "specular", 0.0, 1.0, &m->specular)))
        return r;
    if (m->type == VBL_MATERIAL_PHONG) {
        if ((r = vbl_json_number(ctx, obj, field, "exponent", 0, &m->exponent))) return r;
        if (!(m->exponent >= 0.0)) return vbl_json_fail(ctx, "%s.exponent = %g must be >= 0", field, m->exponent);
    }
    if (m->type == VBL_MATERIAL_GGX) {
        if ((r = vbl_json_number(ctx, obj, field, "roughness", 0, &m->roughness))) return r;
    }
    char prefix[600];
    snprintf(prefix, sizeof prefix, "%s: %s", ctx->path, field);
    return vbl_scene_material_check(m, prefix);
}

/* Re-records the current error as "<scene>: <field>: <message>", keeping its code. */
static vbl_result vbl_wrap_error(vbl_result r, const vbl_json_ctx* ctx, const char* field)
{
    char inner[1024];
    const char* msg = vbl_last_error_message();
    snprintf(inner, sizeof inner, "%s", msg && msg[0] ? msg : vbl_result_name(r));
    return vbl_error(r, "%s: %s: %s", ctx->path, field, inner);
}

static vbl_result vbl_parse_surface(vbl_scene* scene, const vbl_json_ctx* ctx, const cJSON* obj, const char* field,
                                    const char* dir, vbl_surface_color_fn color, const void* colors)
{
    static const char* const keys[] = {"mesh", "transform", "material", "subdivision", NULL};
    static const char* const subdiv_keys[] = {"level", NULL};
    vbl_result r;
    if (!cJSON_IsObject(obj)) return vbl_json_fail(ctx, "%s must be an object", field);
    if ((r = vbl_json_check_keys(ctx, obj, field, keys))) return r;
    const char* mesh_name = NULL;
    if ((r = vbl_json_string(ctx, obj, field, "mesh", 1, &mesh_name))) return r;
    if (!mesh_name[0]) return vbl_json_fail(ctx, "%s.mesh is empty", field);
    char path[2048];
    if (mesh_name[0] == '/')
        snprintf(path, sizeof path, "%s", mesh_name);
    else
        snprintf(path, sizeof path, "%s%s", dir, mesh_name);
    vbl_affine xf;
    vbl_affine_set_identity(&xf);
    const cJSON* t = cJSON_GetObjectItemCaseSensitive(obj, "transform");
    if (t) {
        char tf[256];
        vbl_json_field(tf, sizeof tf, field, "transform");
        if ((r = vbl_parse_matrix(ctx, t, tf, &xf))) return r;
    }
    vbl_material material;
    if ((r = vbl_parse_material(ctx, obj, field, color, colors, &material))) return r;
    int level = -1;
    const cJSON* sub = NULL;
    char sf[256];
    vbl_json_field(sf, sizeof sf, field, "subdivision");
    if ((r = vbl_json_object(ctx, obj, field, "subdivision", 0, &sub))) return r;
    if (sub) {
        if ((r = vbl_json_check_keys(ctx, sub, sf, subdiv_keys))) return r;
        double v = 2.0;
        if ((r = vbl_json_int(ctx, sub, sf, "level", 0, 0, VBL_SUBDIVISION_MAX_LEVEL, &v))) return r;
        level = (int)v;
    }
    char mf[300];
    snprintf(mf, sizeof mf, "%s.mesh = \"%s\"", field, mesh_name);
    vbl_mesh_data mesh;
    size_t dropped = 0;
    if (level >= 0) {
        vbl_poly_mesh poly;
        if ((r = vbl_mesh_load_polygons(path, &poly))) return vbl_wrap_error(r, ctx, mf);
        r = vbl_subdivide(poly.positions, poly.vertex_count, poly.face_sizes, poly.face_count, poly.indices, level,
                          path, &mesh);
        vbl_poly_mesh_free(&poly);
        if (r) return vbl_wrap_error(r, ctx, mf);
    } else if ((r = vbl_mesh_load(path, &mesh, &dropped))) {
        return vbl_wrap_error(r, ctx, mf);
    }
    char what[1200];
    snprintf(what, sizeof what, "%s: %s", ctx->path, field);
    r = vbl_scene_add_mesh_data(scene, &mesh, &material, &xf, what);
    vbl_mesh_data_free(&mesh);
    if (!r) scene->dropped_triangles += dropped;
    return r;
}

vbl_result vbl_scene_parse_surfaces(vbl_scene* scene, const vbl_json_ctx* ctx, const cJSON* root, const char* dir,
                                    vbl_surface_color_fn color, const void* colors)
{
    const cJSON* surfaces = cJSON_GetObjectItemCaseSensitive(root, "surfaces");
    if (!surfaces) return VBL_SUCCESS;
    if (!cJSON_IsArray(surfaces)) return vbl_json_fail(ctx, "surfaces must be an array");
    int i = 0;
    for (const cJSON* s = surfaces->child; s; s = s->next, ++i) {
        char field[64];
        snprintf(field, sizeof field, "surfaces[%d]", i);
        vbl_result r = vbl_parse_surface(scene, ctx, s, field, dir, color, colors);
        if (r) return r;
    }
    return VBL_SUCCESS;
}
