/* Grids of a medium by role (docs/readme/emission.md "Grids by role"): the names each role
 * looks for, and loading one role's float grid with a message naming file, grid and field. */
#ifndef VBL_SCENE_SCENE_GRIDS_H
#define VBL_SCENE_SCENE_GRIDS_H

#include "vbl/vbl_volume.h"

typedef enum vbl_grid_role {
    VBL_ROLE_DENSITY = 0,
    VBL_ROLE_EMISSION = 1,
    VBL_ROLE_TEMPERATURE = 2,
    VBL_ROLE_ALBEDO = 3,
    VBL_ROLE_VELOCITY = 4,
    VBL_ROLE_NONE = 5
} vbl_grid_role;

/* "density", "emission", ... ("" for VBL_ROLE_NONE). */
const char* vbl_grid_role_name(vbl_grid_role role);
/* NULL-terminated grid names a role takes when the scene names none, in order of preference. */
const char* const* vbl_grid_role_names(vbl_grid_role role);
/* The role a grid of this name would get (VBL_ROLE_NONE if none). */
vbl_grid_role vbl_grid_role_for_name(const char* grid_name);

/* Loads role `role` of scene field `field` (e.g. "media[0].emission") from `path`: the grid
 * named `grid` if not NULL, else the first of vbl_grid_role_names(role) in the file. Errors
 * name the scene, the field, the file and the grid (VBL_ERROR_GRID_NOT_FOUND, the loader's
 * VBL_ERROR_GRID_TYPE, VBL_ERROR_BAD_VOXELS ...). */
vbl_result vbl_load_role_grid(const char* scene_path, const char* field, vbl_grid_role role, const char* path,
                              const char* grid, vbl_volume** out);

/* Loads a role that takes a vector (albedo: vec3s/vec3d or float; velocity: vec3s/vec3d or
 * three float grids NAME.x/.y/.z, signed): out[0..2] the x, y, z components (a float albedo
 * grid: the same volume three times, retained thrice). `grid` NULL: the role's names in
 * order; for velocity also the triplet "vel.x"/"vel.y"/"vel.z" (or "<grid>.x"... when the named
 * grid is absent but its triplet is there). Errors as vbl_load_role_grid. */
vbl_result vbl_load_role_vec3(const char* scene_path, const char* field, vbl_grid_role role, const char* path,
                              const char* grid, vbl_volume* out[3]);

#endif
