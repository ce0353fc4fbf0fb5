/* libvbl volumes: OpenVDB/NanoVDB float grids loaded into memory as NanoVDB, sampled through
 * PNanoVDB, with a block majorant grid for empty-space skipping, and transmittance estimators. */
#ifndef VBL_VOLUME_H
#define VBL_VOLUME_H

#include "vbl/vbl_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One float grid in memory (NanoVDB) plus its majorant grid. Opaque, reference counted,
 * immutable after loading: share it freely between threads. */
typedef struct vbl_volume vbl_volume;

/* What vbl_volume_load does with NaN, Inf or negative voxel values. */
typedef enum vbl_bad_voxel_policy {
    VBL_BAD_VOXELS_REJECT = 0,  /* NaN, Inf or negative voxels fail the load (default) */
    VBL_BAD_VOXELS_SANITIZE = 1 /* such voxels are set to 0 and counted (see info) */
} vbl_bad_voxel_policy;

/* Options of vbl_volume_load; initialize with VBL_VOLUME_LOAD_OPTIONS_DEFAULT. */
typedef struct vbl_volume_load_options {
    size_t size;                     /* sizeof(vbl_volume_load_options) */
    const char* grid_name;           /* NULL: "density", else the file's only float grid */
    int grid_index;                  /* >= 0: the grid_index-th grid *of that name* (or of the file
                                        when grid_name is NULL) in file order; -1: first match */
    vbl_bad_voxel_policy bad_voxels; /* NaN/Inf/negative voxels: reject (default) or sanitize */
    int majorant_block_size;         /* majorant block edge in voxels; 0 = library default */
    /* Non-NULL: set *cancel to non-zero (e.g. from a signal handler) to stop the load at its next
     * step (after the file read, the value scan, the majorant build): VBL_ERROR_INTERRUPTED, nothing
     * kept. The file read itself (OpenVDB's readGrid and conversion) is not interrupted. */
    const volatile int* cancel;
} vbl_volume_load_options;

/* Defaults: grid "density" (else the only float grid), first match, reject bad voxels. */
#define VBL_VOLUME_LOAD_OPTIONS_DEFAULT {sizeof(vbl_volume_load_options), NULL, -1, VBL_BAD_VOXELS_REJECT, 0, NULL}

/* Loads a float grid from an OpenVDB (.vdb) or NanoVDB (.nvdb) file. */
VBL_API vbl_result vbl_volume_load(const char* path, const vbl_volume_load_options* options,
                                   vbl_volume** out_volume);
/* Adds a reference to `volume`. */
VBL_API void vbl_volume_retain(vbl_volume* volume);
/* Drops a reference; the last one frees the volume. NULL is ignored. */
VBL_API void vbl_volume_release(vbl_volume* volume);

/* What vbl_volume_get_info reports about a loaded grid. */
typedef struct vbl_volume_info {
    size_t size;                  /* set by the caller: sizeof(vbl_volume_info) */
    char file_path[1024];         /* the file it was loaded from */
    char grid_name[256];          /* the grid's name in the file */
    int grid_index;               /* position of the grid in the file */
    uint64_t active_voxels;       /* voxels stored as active */
    int index_bbox_min[3], index_bbox_max[3]; /* inclusive, of active voxels */
    double world_bbox_min[3], world_bbox_max[3]; /* bounds of the trilinear support */
    double voxel_size[3];         /* world units per voxel along x, y, z */
    double index_to_world[4][4];  /* row-major, column vectors: world = M * (i, j, k, 1) */
    double value_min, value_max, value_mean; /* over active voxels */
    uint64_t nanovdb_bytes;       /* in-memory NanoVDB grid size */
    uint64_t majorant_bytes;      /* size of the majorant grid */
    int majorant_block_size;      /* majorant block edge in voxels */
    uint64_t sanitized_voxels;    /* voxels set to 0 by VBL_BAD_VOXELS_SANITIZE */
} vbl_volume_info;

/* Fills `out_info` (whose size the caller sets) with the grid's description. */
VBL_API vbl_result vbl_volume_get_info(const vbl_volume* volume, vbl_volume_info* out_info);

/* Reconstruction filter for vbl_volume_sample. */
typedef enum vbl_filter {
    VBL_FILTER_NEAREST = 0,   /* the value of the voxel containing the point */
    VBL_FILTER_TRILINEAR = 1  /* OpenVDB BoxSampler convention: voxel (i,j,k) sits at index (i,j,k) */
} vbl_filter;

/* Grid value at a world-space point (convenience; the renderer uses per-thread accessors). */
VBL_API double vbl_volume_sample(const vbl_volume* volume, const double world_point[3], vbl_filter filter);

/* Transmittance estimators (docs/readme/volume.md compares them). */
typedef enum vbl_transmittance_estimator {
    VBL_TRANSMITTANCE_DELTA_TRACKING = 0,          /* Woodcock: binary 0/1 estimate */
    VBL_TRANSMITTANCE_RATIO_TRACKING = 1,          /* product of null-collision ratios (default) */
    VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING = 2, /* control = local minimum density */
    VBL_TRANSMITTANCE_RAY_MARCHING = 3,            /* biased, for previews */
    VBL_TRANSMITTANCE_CACHED_DELTA = 4,            /* VRL paper sec. 6: cached Woodcock distances */
    VBL_TRANSMITTANCE_CACHED_RATIO = 5             /* cached ratio-tracking products */
} vbl_transmittance_estimator;

/* Options of vbl_volume_transmittance; initialize with VBL_TRANSMITTANCE_OPTIONS_DEFAULT. */
typedef struct vbl_transmittance_options {
    size_t size;               /* sizeof(vbl_transmittance_options) */
    vbl_transmittance_estimator estimator; /* which estimator */
    double density_scale;      /* sigma_t = density_scale * grid value, per world unit */
    double march_step;         /* ray marching step in world units; <= 0: adaptive (voxel size) */
    int cache_size;            /* entries per cached estimator; 0 = 16 */
    uint64_t seed;             /* random seed: same seed, same estimates */
} vbl_transmittance_options;

/* Defaults: ratio tracking, density scale 1, adaptive march step, cache size 16, seed 0. */
#define VBL_TRANSMITTANCE_OPTIONS_DEFAULT \
    {sizeof(vbl_transmittance_options), VBL_TRANSMITTANCE_RATIO_TRACKING, 1.0, 0.0, 0, 0}

/* The outcome of vbl_volume_transmittance. */
typedef struct vbl_transmittance_result {
    double mean;        /* mean of the estimates */
    double std_error;   /* standard error of the mean */
    uint64_t lookups;   /* density lookups spent */
} vbl_transmittance_result;

/* Estimates T(tmin, tmax) along origin + t * direction (direction need not be unit: t is the
 * ray parameter) with `samples` independent estimates. */
VBL_API vbl_result vbl_volume_transmittance(const vbl_volume* volume, const double origin[3],
                                            const double direction[3], double tmin, double tmax,
                                            const vbl_transmittance_options* options,
                                            unsigned samples, vbl_transmittance_result* out);

/* Name of an estimator ("delta", "ratio", "residual", "march", "cached-delta", "cached-ratio");
 * vbl_transmittance_estimator_parse returns VBL_ERROR_INVALID_ARGUMENT for unknown names. */
VBL_API const char* vbl_transmittance_estimator_name(vbl_transmittance_estimator estimator);
/* The estimator of a name returned by vbl_transmittance_estimator_name. */
VBL_API vbl_result vbl_transmittance_estimator_parse(const char* name, vbl_transmittance_estimator* out);

/* ---- Grid listing (for `vbl info`; VDB loading, issue 2) ---------------------------------- */

/* One grid of a .vdb/.nvdb file as stored (float or not), in file order. */
typedef struct vbl_grid_description {
    char name[256];           /* the grid's name */
    char type[64];            /* "float", "half float", "vec3s", "int32", ... */
    int is_float;             /* loadable with vbl_volume_load */
    uint64_t active_voxels;   /* voxels stored as active */
    int index_bbox_min[3], index_bbox_max[3]; /* inclusive; min > max when empty */
    double voxel_size[3];     /* world units per voxel along x, y, z */
    char codec[64];           /* "blosc + active mask", "zip + active mask", "nanovdb BLOSC", ... */
} vbl_grid_description;

/* The role a scene medium gives a grid of this name when the scene names no grid for that role
 * ("density", "emission", "temperature", "albedo", "velocity"; docs/readme/emission.md), or
 * NULL if the name has no role. */
VBL_API const char* vbl_grid_role_for(const char* grid_name);

/* Lists every grid of a file; free the array with vbl_grid_descriptions_free. */
VBL_API vbl_result vbl_file_list_grids(const char* path, vbl_grid_description** out_grids, size_t* out_count);
VBL_API void vbl_grid_descriptions_free(vbl_grid_description* grids);

#ifdef __cplusplus
}
#endif

#endif /* VBL_VOLUME_H */
