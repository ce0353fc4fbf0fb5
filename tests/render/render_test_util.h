/* Helpers for render tests: temporary directories and files, in-memory constant boxes. */
#ifndef VBL_RENDER_TEST_UTIL_H
#define VBL_RENDER_TEST_UTIL_H

#include <stdint.h>

#include "scene/scene.h"
#include "vbl/vbl.h"

/* mkdtemp under $TMPDIR (or /tmp); the path is written into `out` (size >= 256). */
void rt_make_temp_dir(char* out);
/* Writes `text` to dir/name; returns the full path in `out` (size >= 512). */
void rt_write_file(const char* dir, const char* name, const char* text, char* out);
/* Removes every regular file in `dir` and the directory (one level). */
void rt_remove_dir(const char* dir);
/* A cmocka group fixture around a temporary directory: rt_temp_dir_setup makes it
 * (rt_make_temp_dir) into rt_temp_dir, rt_temp_dir_teardown removes it (rt_remove_dir). */
extern char rt_temp_dir[256];
int rt_temp_dir_setup(void** state);
int rt_temp_dir_teardown(void** state);

/* The scene file of the film-merge tests (film merge, hybrid): the fixture box.vdb (density 3,
 * albedo (0.9, 0.8, 0.7), HG g 0.3) under a distant light and a blue environment, 12 x 9, 4
 * passes x 2 spp, seed 5, 40 light paths; written with vbl_test_temp_scene_write(prefix, ...).
 * Returns 0, or -1 without VBL_FIXTURE_DIR or on a write error. */
int rt_merge_scene_write(const char* prefix, char* path, size_t path_size);

/* The group fixture of the render-loop tests (cancel, stop phases): rt_lit_box_setup writes a
 * scene file (vbl_test_temp_scene_write: the fixture box.vdb with albedo 0.8 and `density_scale`,
 * lit from above by a distant light, seen from -y at fov 40 and w x h) and loads it into
 * rt_lit_box, returning 0 or -1; rt_lit_box_teardown releases the scene and removes the file. */
extern vbl_scene* rt_lit_box;
int rt_lit_box_setup(int w, int h, double density_scale);
int rt_lit_box_teardown(void** state);

/* The albedo_ramp.vdb box of the vrl agreement tests (vrl bias, light guide): seen from -y at fov 20
 * and res x res, lit by a slanted distant light (irradiance 2), with `density_scale`, a constant
 * `albedo` and `medium_extra` appended to the medium (further fields such as
 * ", \"phase\": {...}", or ""). Written into rt_temp_dir (rt_temp_dir_setup) and loaded; NULL
 * (the message printed) on failure. */
vbl_scene* rt_ramp_box_load(double density_scale, double albedo, int res, const char* medium_extra);

/* The mean over pixels and RGB of `film`'s layer `layer` into *mean; -1 if the layer is missing or
 * a value is not finite, else 0. */
int rt_layer_mean(const vbl_film* film, const char* layer, double* mean);
/* n renders of `scene` with `base` and seeds seed0 + k: the mean of their rt_layer_mean and its
 * standard error across the renders; -1 on a render error (the message printed) or a failed
 * rt_layer_mean, else 0. */
int rt_layer_replicas(const vbl_scene* scene, const vbl_render_options* base, const char* layer, int n,
                      uint64_t seed0, double* mean, double* se);

/* A constant-value box volume: n^3 active voxels of value 1, voxel size h, voxel (0,0,0) at
 * world `origin` (OpenVDB convention: trilinear density 1 on [origin, origin + (n-1) h]^3,
 * falling linearly to 0 within one voxel outside). */
vbl_volume* rt_make_box(int n, double h, vbl_vec3 origin);
/* The exact trilinear density of rt_make_box at a world point. */
double rt_box_density(int n, double h, vbl_vec3 origin, vbl_vec3 p);

/* A camera at `position` looking at `target`, up +z. */
vbl_camera rt_camera(vbl_vec3 position, vbl_vec3 target, double fov_deg, int w, int h);

#endif
