/* The scene model built from a JSON scene file: pinhole camera, lights, media (VDB volumes with
 * density scale, albedo, HG phase, placement), opaque surfaces (meshes + materials,
 * scene_surfaces.h) and the render block. Immutable after loading. */
#ifndef VBL_SCENE_SCENE_H
#define VBL_SCENE_SCENE_H

#include <stddef.h>

#include "core/math.h"
#include "geometry/surfaces.h"
#include "material/material.h"
#include "vbl/vbl_render.h"
#include "scene/emission_lights.h"
#include "volume/blackbody.h"
#include "volume/extinction.h"

#define VBL_MAX_LIGHTS 64
#define VBL_MAX_LIGHT_GROUPS 8 /* "default" (untagged lights, emissive media) + 7 named */

/* Pinhole camera (Cycles reference kit convention, see docs/readme/render.md). */
typedef struct vbl_camera {
    vbl_vec3 position;
    vbl_vec3 forward, right, up; /* f, r = normalize(cross(f, up)), u = cross(r, f) */
    double tan_half_fov;         /* tan(vfov / 2) */
    int width, height;
} vbl_camera;

typedef enum vbl_light_type {
    VBL_LIGHT_POINT = 0,
    VBL_LIGHT_SPOT = 1,
    VBL_LIGHT_DISTANT = 2,
    VBL_LIGHT_QUAD = 3,
    VBL_LIGHT_ENVIRONMENT = 4
} vbl_light_type;

typedef struct vbl_light {
    vbl_light_type type;
    vbl_vec3 color;      /* point/spot: intensity W/sr; distant: irradiance W/m^2;
                            quad/environment: radiance W/(m^2 sr) */
    vbl_vec3 position;   /* point, spot */
    vbl_vec3 direction;  /* spot: unit axis (direction of emission); distant: unit travel dir */
    double cos_inner, cos_outer; /* spot: cosines of the inner/outer half-angles */
    vbl_vec3 corner, edge1, edge2; /* quad */
    vbl_vec3 normal;     /* quad: unit cross(edge1, edge2), the emitting side */
    double area;         /* quad */
    int group;           /* index into vbl_scene.light_groups (0: "default", the untagged lights) */
} vbl_light;

typedef struct vbl_medium {
    vbl_volume* volume;
    char vdb_path[1024]; /* resolved */
    double density_scale;
    vbl_vec3 albedo;
    double g;            /* Henyey-Greenstein asymmetry in (-1, 1) */
    vbl_affine volume_to_scene;
    vbl_affine scene_to_volume;
    /* Emission (docs/readme/emission.md): radiance per unit length sigma_a(x) Le(x) with
     * Le = emission_scale * emission_color * E(x) + blackbody_intensity * B(T(x) * temperature_scale +
     * temperature_offset); E, T are float grids (NULL: that term is absent), each sampled in its
     * own file's world space through scene_to_volume. */
    vbl_volume* emission_volume;
    vbl_vec3 emission_color;
    double emission_scale;
    vbl_volume* temperature_volume;
    double temperature_scale, temperature_offset, blackbody_intensity;
    vbl_blackbody_table blackbody; /* built when temperature_volume is set */
    int emissive;                  /* some term can emit (and the medium absorbs somewhere) */
    /* Per-voxel albedo (docs/readme/emission.md "Grids by role"): albedo(x) = albedo * A(x) per
     * channel, A from a vec3s grid (three component volumes) or a float grid (the same volume
     * three times); NULL: constant albedo. albedo_min: its smallest value per channel (a bound). */
    vbl_volume* albedo_volume[3];
    vbl_vec3 albedo_min;
    /* Velocity (motion blur, docs/readme/emission.md "Motion blur"): in the file's world units per
     * second, times velocity.scale; velocity.v[0] NULL: none. The volumes are owned (released with
     * the scene). */
    vbl_velocity_field velocity;
} vbl_medium;

struct vbl_scene {
    int refcount;
    char path[1024];
    char color_space[256]; /* top-level "color_space" as written; "" when absent */
    vbl_camera camera;
    vbl_light lights[VBL_MAX_LIGHTS];
    int light_count;
    int has_delta_lights;   /* point/spot/distant */
    int has_visible_lights; /* quad/environment (seen directly -> background layer) */
    /* light groups (docs/readme/output.md, "Light groups"): names[0] = "default"; count 0 when no
     * light has a "group" (then options.light_groups adds nothing) */
    char light_groups[VBL_MAX_LIGHT_GROUPS][24];
    int light_group_count;
    vbl_medium media[VBL_MAX_MEDIA];
    int media_count;
    vbl_extinction extinction; /* components in media order */
    int has_emission;          /* some medium is emissive (decided once at load) */
    vbl_emission_lights emission_lights; /* emissive media as light sources (pt's NEE) */
    int emission_nee;          /* 1 (default): pt samples emissive media as lights (MIS with phase/BRDF
                                  sampling); 0: emission only by tracking (tests compare the two) */
    int has_albedo_grids;      /* some medium has an albedo grid */
    /* Motion blur: camera.shutter [open, close] in frames at `fps`, here in seconds relative to the
     * frame; `motion` = some medium has a velocity grid and the shutter is open for a while (set
     * at load; the render option motion_blur = 0 renders at time 0 instead). */
    double fps;
    double shutter_open, shutter_close;
    int motion;
    /* surfaces (docs/readme/surfaces.md): NULL/0 for media-only scenes, which then never call
     * Embree. Surface i uses materials[i]. */
    vbl_surfaces* surfaces;
    vbl_material* materials;
    int surface_count;
    int has_surfaces;
    size_t dropped_triangles; /* degenerate / non-triangle faces dropped while loading */
    vbl_render_options render; /* the scene's render block (defaults filled in) */
};

/* Camera ray through continuous raster position (sx, sy), sy down from the top. */
void vbl_camera_ray(const vbl_camera* camera, double sx, double sy, vbl_vec3* origin, vbl_vec3* direction);
/* The inverse: the raster position of scene point p; 0 if p is not in front of the camera. */
int vbl_camera_raster(const vbl_camera* camera, vbl_vec3 p, double* sx, double* sy);

/* The scene-space box of the media's majorant grids (what tracking sees); 0 without media.
 * (scene_camera.c frames the volumes' world bounding boxes instead: their active voxels.) */
int vbl_scene_media_box(const vbl_scene* scene, vbl_vec3* lo, vbl_vec3* hi);

/* Programmatic scene building (tests, bindings): a scene with only a camera, then media and
 * lights appended. add_medium retains `volume`; volume_to_scene NULL = identity. */
vbl_result vbl_scene_create_empty(const char* name, const vbl_camera* camera, vbl_scene** out_scene);
vbl_result vbl_scene_add_medium(vbl_scene* scene, vbl_volume* volume, double density_scale, vbl_vec3 albedo,
                                double g, const vbl_affine* volume_to_scene);
vbl_result vbl_scene_add_light(vbl_scene* scene, const vbl_light* light);
/* Appends a triangle mesh (positions: 3 * vertex_count doubles, indices: 3 * triangle_count)
 * with `material` (validated) placed by `to_scene` (NULL = identity). Degenerate triangles are
 * dropped (counted in scene->dropped_triangles); no triangle left is an error. */
vbl_result vbl_scene_add_mesh(vbl_scene* scene, const double* positions, size_t vertex_count, const unsigned* indices,
                              size_t triangle_count, const vbl_material* material, const vbl_affine* to_scene);
/* Appends an already loaded mesh (normals optional); `what` names it in messages. */
vbl_result vbl_scene_add_mesh_data(vbl_scene* scene, const vbl_mesh_data* mesh, const vbl_material* material,
                                   const vbl_affine* to_scene, const char* what);
/* Frees the scene's surfaces and materials (scene release). */
void vbl_scene_free_surfaces(vbl_scene* scene);
/* Camera from the JSON fields (position, look_at, up, vertical fov in degrees, resolution). */
vbl_result vbl_camera_make(vbl_vec3 position, vbl_vec3 look_at, vbl_vec3 up, double fov_deg, int width, int height,
                           vbl_camera* out);

#endif
