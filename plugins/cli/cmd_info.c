/* `vbl info FILE [--grid NAME] [--grid-index N] [--sanitize]`: describes the grids of a .vdb/.nvdb
 * file (docs/readme/vdb.md). Float grids are loaded to report values, transform and footprints. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static void vbl_info_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl info FILE [--grid NAME] [--grid-index N] [--sanitize]\n\n"
            "Describes every grid of an OpenVDB (.vdb) or NanoVDB (.nvdb) file: name, type, codec, voxel size,\n"
            "transform, active voxels, index and world bounding boxes, value range and memory footprints.\n\n"
            "  --grid NAME       only the grid called NAME (the first one unless --grid-index is given)\n"
            "  --grid-index N    the N-th grid called NAME, or the N-th grid of the file without --grid\n"
            "  --sanitize        set NaN/Inf/negative values to 0 (and count them) instead of failing\n"
            "  -h, --help        this help\n\n"
            "Exit status: 0 ok, 2 bad command line, 3 missing/corrupt file, bad grid or bad voxels.\n");
}

static void vbl_info_print_bbox_i(const char* label, const int lo[3], const int hi[3], uint64_t active)
{
    if (!active) printf("    %-16s empty\n", label);
    else printf("    %-16s [%d, %d, %d] -> [%d, %d, %d]\n", label, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

static void vbl_info_print_bytes(const char* label, uint64_t bytes)
{
    printf("    %-16s %llu bytes (%.3f MB)\n", label, (unsigned long long)bytes, (double)bytes / (1024.0 * 1024.0));
}

/* Loads and prints one float grid; returns the load result. */
static vbl_result vbl_info_print_volume(const char* path, const char* name, int index, int sanitize)
{
    vbl_volume_load_options options = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    options.grid_name = name;
    options.grid_index = index;
    options.bad_voxels = sanitize ? VBL_BAD_VOXELS_SANITIZE : VBL_BAD_VOXELS_REJECT;
    vbl_volume* volume = NULL;
    vbl_result result = vbl_volume_load(path, &options, &volume);
    if (result != VBL_SUCCESS) {
        printf("    %-16s %s\n", "load failed:", vbl_last_error_message());
        return result;
    }
    vbl_volume_info info;
    memset(&info, 0, sizeof info);
    info.size = sizeof info;
    vbl_volume_get_info(volume, &info);
    printf("    %-16s %.17g %.17g %.17g\n", "voxel size:", info.voxel_size[0], info.voxel_size[1], info.voxel_size[2]);
    for (int r = 0; r < 4; ++r)
        printf("    %-16s [%.17g, %.17g, %.17g, %.17g]\n", r ? "" : "index to world:", info.index_to_world[r][0],
               info.index_to_world[r][1], info.index_to_world[r][2], info.index_to_world[r][3]);
    printf("    %-16s %llu\n", "active voxels:", (unsigned long long)info.active_voxels);
    vbl_info_print_bbox_i("index bbox:", info.index_bbox_min, info.index_bbox_max, info.active_voxels);
    if (info.active_voxels) {
        printf("    %-16s (%.9g, %.9g, %.9g) -> (%.9g, %.9g, %.9g)  (trilinear support)\n", "world bbox:",
               info.world_bbox_min[0], info.world_bbox_min[1], info.world_bbox_min[2], info.world_bbox_max[0],
               info.world_bbox_max[1], info.world_bbox_max[2]);
        printf("    %-16s min %.9g  max %.9g  mean %.9g\n", "values:", info.value_min, info.value_max, info.value_mean);
    } else {
        printf("    %-16s empty\n", "world bbox:");
        printf("    %-16s none (no active voxels)\n", "values:");
    }
    if (sanitize) printf("    %-16s %llu\n", "sanitized:", (unsigned long long)info.sanitized_voxels);
    vbl_info_print_bytes("nanovdb memory:", info.nanovdb_bytes);
    vbl_info_print_bytes("majorant:", info.majorant_bytes);
    printf("    %-16s %d voxels\n", "majorant block:", info.majorant_block_size);
    vbl_volume_release(volume);
    return VBL_SUCCESS;
}

int vbl_cmd_info(int argc, char** argv)
{
    const char* path = NULL;
    const char* grid_name = NULL;
    int grid_index = -1, sanitize = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            vbl_info_usage(stdout);
            return VBL_EXIT_OK;
        } else if (!strcmp(argv[i], "--grid") && i + 1 < argc) {
            grid_name = argv[++i];
        } else if (!strcmp(argv[i], "--grid-index") && i + 1 < argc) {
            char* end = NULL;
            errno = 0;
            long n = strtol(argv[++i], &end, 10);
            if (errno || !end || *end || n < 0 || n > 1000000) {
                fprintf(stderr, "vbl: info: --grid-index '%s' is not a non-negative integer\n", argv[i]);
                return VBL_EXIT_USAGE;
            }
            grid_index = (int)n;
        } else if (!strcmp(argv[i], "--sanitize")) {
            sanitize = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            fprintf(stderr, "vbl: info: unknown or incomplete option '%s' (see 'vbl info --help')\n", argv[i]);
            return VBL_EXIT_USAGE;
        } else if (!path) {
            path = argv[i];
        } else {
            fprintf(stderr, "vbl: info: more than one file given ('%s', '%s')\n", path, argv[i]);
            return VBL_EXIT_USAGE;
        }
    }
    if (!path) {
        vbl_info_usage(stderr);
        return VBL_EXIT_USAGE;
    }

    vbl_grid_description* grids = NULL;
    size_t count = 0;
    vbl_result result = vbl_file_list_grids(path, &grids, &count);
    if (result != VBL_SUCCESS) return vbl_cli_fail(result);

    printf("file: %s\ngrids: %zu\n", path, count);
    vbl_result first_failure = VBL_SUCCESS;
    char failure_message[2048] = "";
    if (grid_name || grid_index >= 0) {
        /* One grid, chosen by the library's selection rules. */
        result = vbl_info_print_volume(path, grid_name, grid_index, sanitize);
        if (result != VBL_SUCCESS) {
            first_failure = result;
            snprintf(failure_message, sizeof failure_message, "%s", vbl_last_error_message());
        }
    } else {
        for (size_t g = 0; g < count; ++g) {
            const vbl_grid_description* d = &grids[g];
            printf("[%zu] '%s' %s\n", g, d->name, d->type);
            const char* role = vbl_grid_role_for(d->name);
            const int vector = strstr(d->type, "vec3") != NULL || strstr(d->type, "Vec3") != NULL;
            const int vector_role = role && (!strcmp(role, "albedo") || !strcmp(role, "velocity"));
            const size_t len = strlen(d->name);
            const int component = len > 2 && d->name[len - 2] == '.' && strchr("xyz", d->name[len - 1]);
            const char* detail = "";
            if (!role && vector) detail = " (a vector grid: name it as a medium's albedo.grid or velocity.grid)";
            else if (!role) detail = " (name it in the scene to use it)";
            else if (vector_role && vector) detail = " (vector: x, y, z components)";
            else if (vector_role && component && !strcmp(role, "velocity")) detail = " (one component of a float triplet)";
            else if (!strcmp(role, "velocity")) detail = " (needs a vec3s grid or a .x/.y/.z triplet)";
            else if (vector) detail = " (a vector grid: this role needs a float grid)";
            printf("    %-16s %s%s\n", "role:", role ? role : "none", detail);
            printf("    %-16s %s\n", "codec:", d->codec);
            if (!d->is_float) {
                printf("    %-16s %.17g %.17g %.17g\n", "voxel size:", d->voxel_size[0], d->voxel_size[1], d->voxel_size[2]);
                printf("    %-16s %llu\n", "active voxels:", (unsigned long long)d->active_voxels);
                vbl_info_print_bbox_i("index bbox:", d->index_bbox_min, d->index_bbox_max, d->active_voxels);
                printf("    %-16s %s\n", "note:",
                       vector_role && vector ? "a vector grid (loaded by its role, not as a density volume)"
                                             : "not a float grid (not loadable as a volume)");
                continue;
            }
            int same_name_before = 0; /* the n-th grid of this name, for duplicate names */
            for (size_t k = 0; k < g; ++k) same_name_before += !strcmp(grids[k].name, d->name);
            result = vbl_info_print_volume(path, d->name, same_name_before, sanitize);
            if (result != VBL_SUCCESS && first_failure == VBL_SUCCESS) {
                first_failure = result;
                snprintf(failure_message, sizeof failure_message, "%s", vbl_last_error_message());
            }
        }
    }
    vbl_grid_descriptions_free(grids);
    if (first_failure != VBL_SUCCESS) {
        fflush(stdout);
        fprintf(stderr, "vbl: %s\n", failure_message);
        return vbl_cli_exit_code(first_failure);
    }
    return VBL_EXIT_OK;
}
