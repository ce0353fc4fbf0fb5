/* Loading volumes: vbl_volume_load (file -> adapter -> NanoVDB buffer), vbl_volume_create_from_nanovdb
 * (handles, transforms, statistics, bad-voxel policy, majorant grid), retain/release and info.
 *
 * The value scan walks the node arrays of the NanoVDB buffer level by level (NanoVDB stores each level
 * contiguously; the adapter validates that every child pointer lands in its level's array), so every
 * stored value the sampler can read is visited once: leaf voxels (active and inactive), internal and
 * root tile values (active and inactive) and the background. */
#include "volume/volume.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/error.h"
#include "vbl_vdb_adapter.h"

#define VBL_FLOAT_GRID PNANOVDB_GRID_TYPE_FLOAT

/* Running statistics of the scan. */
typedef struct vbl_scan {
    vbl_bad_voxel_policy policy;
    int allow_negative; /* signed grids (velocity components): only NaN/Inf are bad */
    uint64_t active_voxels;
    double sum, vmin, vmax;
    int bmin[3], bmax[3];
    uint64_t bad_nan, bad_inf, bad_negative; /* stored values (a tile counts once) */
    uint64_t bad_active, bad_inactive;
} vbl_scan;

static float* vbl_value_ptr(void* buffer, pnanovdb_address_t address)
{
    return (float*)((char*)buffer + address.byte_offset);
}

/* Checks one stored value; sanitizes it in place under VBL_BAD_VOXELS_SANITIZE. Returns the value. */
static float vbl_scan_check(vbl_scan* scan, float* value, int active)
{
    float v = *value;
    if (!(v >= 0.0f || (scan->allow_negative && v < 0.0f)) || isinf(v)) {
        if (isnan(v)) ++scan->bad_nan;
        else if (isinf(v)) ++scan->bad_inf;
        else ++scan->bad_negative;
        if (active) ++scan->bad_active;
        else ++scan->bad_inactive;
        if (scan->policy == VBL_BAD_VOXELS_SANITIZE) *value = v = 0.0f;
    }
    return v;
}

static void vbl_scan_active(vbl_scan* scan, double v, uint64_t count, int x, int y, int z, int extent)
{
    scan->active_voxels += count;
    scan->sum += v * (double)count;
    if (v < scan->vmin) scan->vmin = v;
    if (v > scan->vmax) scan->vmax = v;
    int lo[3] = {x, y, z};
    for (int a = 0; a < 3; ++a) {
        if (lo[a] < scan->bmin[a]) scan->bmin[a] = lo[a];
        if (lo[a] + extent - 1 > scan->bmax[a]) scan->bmax[a] = lo[a] + extent - 1;
    }
}

static int vbl_mask_bit(const void* buffer, pnanovdb_address_t node, uint32_t offset, uint32_t n)
{
    const uint32_t* words = (const uint32_t*)((const char*)buffer + node.byte_offset + offset);
    return (int)((words[n >> 5] >> (n & 31u)) & 1u);
}

static void vbl_scan_leaves(vbl_volume* v, vbl_scan* scan, pnanovdb_tree_handle_t tree)
{
    uint32_t count = pnanovdb_tree_get_node_count_leaf(v->buf, tree);
    uint64_t first = pnanovdb_tree_get_node_offset_leaf(v->buf, tree);
    uint32_t stride = PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, leaf_size);
    uint32_t table = PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, leaf_off_table);
    for (uint32_t l = 0; l < count; ++l) {
        pnanovdb_leaf_handle_t leaf = {pnanovdb_address_offset64(tree.address, first + (uint64_t)l * stride)};
        pnanovdb_coord_t o = pnanovdb_leaf_get_bbox_min(v->buf, leaf);
        int ox = o.x & ~7, oy = o.y & ~7, oz = o.z & ~7;
        const uint64_t* mask = (const uint64_t*)((const char*)v->nanovdb_buffer + leaf.address.byte_offset + PNANOVDB_LEAF_OFF_VALUE_MASK);
        float* values = (float*)((char*)v->nanovdb_buffer + leaf.address.byte_offset + table);
        for (uint32_t n = 0; n < 512; ++n) {
            int active = (int)((mask[n >> 6] >> (n & 63u)) & 1u);
            float value = vbl_scan_check(scan, &values[n], active);
            if (active) vbl_scan_active(scan, value, 1, ox + (int)(n >> 6), oy + (int)((n >> 3) & 7u), oz + (int)(n & 7u), 1);
        }
    }
}

/* Internal nodes: lower (level 1, 16^3 tiles of 8^3 voxels) or upper (level 2, 32^3 tiles of 128^3). */
static void vbl_scan_internal(vbl_volume* v, vbl_scan* scan, pnanovdb_tree_handle_t tree, int level)
{
    const int upper = level == 2;
    uint32_t count = upper ? pnanovdb_tree_get_node_count_upper(v->buf, tree) : pnanovdb_tree_get_node_count_lower(v->buf, tree);
    uint64_t first = upper ? pnanovdb_tree_get_node_offset_upper(v->buf, tree) : pnanovdb_tree_get_node_offset_lower(v->buf, tree);
    uint32_t stride = upper ? PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, upper_size) : PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, lower_size);
    uint32_t log2dim = upper ? 5u : 4u, child_log2 = upper ? 7u : 3u, entries = 1u << (3u * log2dim);
    uint32_t value_mask = upper ? PNANOVDB_UPPER_OFF_VALUE_MASK : PNANOVDB_LOWER_OFF_VALUE_MASK;
    uint32_t child_mask = upper ? PNANOVDB_UPPER_OFF_CHILD_MASK : PNANOVDB_LOWER_OFF_CHILD_MASK;
    int extent = 1 << child_log2, node_mask = ~((1 << (child_log2 + log2dim)) - 1);
    uint32_t dim_mask = (1u << log2dim) - 1u;
    for (uint32_t i = 0; i < count; ++i) {
        pnanovdb_address_t node = pnanovdb_address_offset64(tree.address, first + (uint64_t)i * stride);
        pnanovdb_coord_t o = pnanovdb_read_coord(v->buf, node); /* bbox min, first member */
        int ox = o.x & node_mask, oy = o.y & node_mask, oz = o.z & node_mask;
        for (uint32_t n = 0; n < entries; ++n) {
            if (vbl_mask_bit(v->nanovdb_buffer, node, child_mask, n)) continue;
            int active = vbl_mask_bit(v->nanovdb_buffer, node, value_mask, n);
            pnanovdb_address_t address = upper ? pnanovdb_upper_get_table_address(VBL_FLOAT_GRID, v->buf, (pnanovdb_upper_handle_t){node}, n)
                                               : pnanovdb_lower_get_table_address(VBL_FLOAT_GRID, v->buf, (pnanovdb_lower_handle_t){node}, n);
            float value = vbl_scan_check(scan, vbl_value_ptr(v->nanovdb_buffer, address), active);
            if (active) {
                int x = ox + (int)((n >> (2u * log2dim)) & dim_mask) * extent;
                int y = oy + (int)((n >> log2dim) & dim_mask) * extent;
                int z = oz + (int)(n & dim_mask) * extent;
                vbl_scan_active(scan, value, (uint64_t)extent * extent * extent, x, y, z, extent);
            }
        }
    }
}

static void vbl_scan_root(vbl_volume* v, vbl_scan* scan)
{
    uint32_t tiles = pnanovdb_root_get_tile_count(v->buf, v->root);
    for (uint32_t t = 0; t < tiles; ++t) {
        pnanovdb_root_tile_handle_t tile = pnanovdb_root_get_tile(VBL_FLOAT_GRID, v->root, t);
        if (!pnanovdb_int64_is_zero(pnanovdb_root_tile_get_child(v->buf, tile))) continue;
        int active = pnanovdb_root_tile_get_state(v->buf, tile) != 0;
        float value = vbl_scan_check(scan, vbl_value_ptr(v->nanovdb_buffer, pnanovdb_root_tile_get_value_address(VBL_FLOAT_GRID, v->buf, tile)), active);
        if (active) {
            uint64_t key = pnanovdb_root_tile_get_key(v->buf, tile); /* 21 bits per axis: i, j, k >> 12 */
            int x = (int)(uint32_t)(((key >> 42) & 0x1FFFFFu) << 12);
            int y = (int)(uint32_t)(((key >> 21) & 0x1FFFFFu) << 12);
            int z = (int)(uint32_t)((key & 0x1FFFFFu) << 12);
            vbl_scan_active(scan, value, (uint64_t)4096 * 4096 * 4096, x, y, z, 4096);
        }
    }
    /* The background is what the sampler returns outside the tree. */
    vbl_scan_check(scan, vbl_value_ptr(v->nanovdb_buffer, pnanovdb_address_offset(v->root.address, PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, root_off_background))), 0);
}

/* Checks what the C side relies on before touching the buffer: header, float type and that the
 * three node arrays and the root tile table lie inside it. (Buffers from the adapter are also
 * checked pointer by pointer there.) */
static vbl_result vbl_check_buffer(const void* buffer, size_t size, const char* path)
{
    if (!buffer || ((uintptr_t)buffer & 31u)) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: NanoVDB buffer is NULL or not 32-byte aligned", path);
    if (size < PNANOVDB_GRID_SIZE + PNANOVDB_TREE_SIZE + PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, root_size))
        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: NanoVDB buffer of %zu bytes is too small", path, size);
    pnanovdb_buf_t buf = pnanovdb_make_buf((uint32_t*)buffer, size / 4);
    pnanovdb_grid_handle_t grid = {pnanovdb_address_null()};
    if (pnanovdb_grid_get_magic(buf, grid) != PNANOVDB_MAGIC_NUMBER) return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: not a NanoVDB grid", path);
    if (pnanovdb_grid_get_grid_type(buf, grid) != PNANOVDB_GRID_TYPE_FLOAT) return vbl_error(VBL_ERROR_GRID_TYPE, "%s: not a float grid", path);
    if (pnanovdb_grid_get_grid_size(buf, grid) > size) return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: NanoVDB grid larger than its buffer", path);
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(buf, grid);
    const uint64_t tree_off = tree.address.byte_offset;
    const uint64_t offs[3] = {pnanovdb_tree_get_node_offset_leaf(buf, tree), pnanovdb_tree_get_node_offset_lower(buf, tree),
                              pnanovdb_tree_get_node_offset_upper(buf, tree)};
    const uint64_t counts[3] = {pnanovdb_tree_get_node_count_leaf(buf, tree), pnanovdb_tree_get_node_count_lower(buf, tree),
                                pnanovdb_tree_get_node_count_upper(buf, tree)};
    const uint64_t strides[3] = {PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, leaf_size), PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, lower_size),
                                 PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, upper_size)};
    for (int l = 0; l < 3; ++l)
        if (counts[l] && (offs[l] > size || tree_off + offs[l] > size || counts[l] > (size - tree_off - offs[l]) / strides[l]))
            return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: NanoVDB node array %d lies outside the buffer", path, l);
    uint64_t root_off = pnanovdb_tree_get_node_offset_root(buf, tree);
    uint64_t root_size = PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, root_size);
    if (root_off > size || tree_off + root_off + root_size > size)
        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: NanoVDB root lies outside the buffer", path);
    pnanovdb_root_handle_t root = pnanovdb_tree_get_root(buf, tree);
    uint64_t tiles = pnanovdb_root_get_tile_count(buf, root);
    if (tiles > (size - tree_off - root_off - root_size) / PNANOVDB_GRID_TYPE_GET(VBL_FLOAT_GRID, root_tile_size))
        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: NanoVDB root tile table lies outside the buffer", path);
    return VBL_SUCCESS;
}

static void vbl_set_transforms(vbl_volume* v)
{
    pnanovdb_map_handle_t map = pnanovdb_grid_get_map(v->buf, v->grid);
    /* NanoVDB's Map: world = M * ijk + t with M row-major (mMatD), and its stored inverse. */
    double t[3], inv_t[3];
    for (int r = 0; r < 3; ++r) t[r] = pnanovdb_map_get_vecd(v->buf, map, (uint32_t)r);
    for (int r = 0; r < 3; ++r) {
        inv_t[r] = 0.0;
        for (int c = 0; c < 3; ++c) {
            double m = pnanovdb_map_get_matd(v->buf, map, (uint32_t)(3 * r + c));
            double im = pnanovdb_map_get_invmatd(v->buf, map, (uint32_t)(3 * r + c));
            v->index_to_world.m[r][c] = m;
            v->world_to_index.m[r][c] = im;
            inv_t[r] -= im * t[c];
        }
    }
    for (int r = 0; r < 3; ++r) {
        v->index_to_world.m[r][3] = t[r];
        v->world_to_index.m[r][3] = inv_t[r];
    }
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) v->info.index_to_world[r][c] = r < 3 ? v->index_to_world.m[r][c] : (c == 3 ? 1.0 : 0.0);
    for (int a = 0; a < 3; ++a) v->info.voxel_size[a] = pnanovdb_grid_get_voxel_size(v->buf, v->grid, (uint32_t)a);
}

/* World bounds of the trilinear support: index box [min - 1, max + 1] (BoxSampler reads voxels
 * floor(p) and floor(p) + 1), all 8 corners through the affine map. */
static void vbl_set_world_bbox(vbl_volume* v)
{
    vbl_volume_info* info = &v->info;
    if (info->active_voxels == 0) {
        memset(info->world_bbox_min, 0, sizeof info->world_bbox_min);
        memset(info->world_bbox_max, 0, sizeof info->world_bbox_max);
        return;
    }
    for (int a = 0; a < 3; ++a) {
        info->world_bbox_min[a] = HUGE_VAL;
        info->world_bbox_max[a] = -HUGE_VAL;
    }
    for (int c = 0; c < 8; ++c) {
        vbl_vec3 p = vbl_v3((c & 1) ? info->index_bbox_max[0] + 1.0 : info->index_bbox_min[0] - 1.0,
                            (c & 2) ? info->index_bbox_max[1] + 1.0 : info->index_bbox_min[1] - 1.0,
                            (c & 4) ? info->index_bbox_max[2] + 1.0 : info->index_bbox_min[2] - 1.0);
        vbl_vec3 w = vbl_affine_point(&v->index_to_world, p);
        for (int a = 0; a < 3; ++a) {
            double x = vbl_v3_get(w, a);
            if (x < info->world_bbox_min[a]) info->world_bbox_min[a] = x;
            if (x > info->world_bbox_max[a]) info->world_bbox_max[a] = x;
        }
    }
}

static void vbl_volume_destroy(vbl_volume* v)
{
    if (!v) return;
    vbl_majorant_grid_free(&v->majorant);
    vbl_aligned_free(v->nanovdb_buffer);
    free(v);
}

vbl_result vbl_volume_create_from_nanovdb(void* buffer, size_t size, const char* path, int grid_index,
                                          const vbl_volume_load_options* options, vbl_volume** out_volume)
{
    return vbl_volume_create_signed(buffer, size, path, grid_index, options, 0, out_volume);
}

vbl_result vbl_volume_create_signed(void* buffer, size_t size, const char* path, int grid_index,
                                    const vbl_volume_load_options* options, int allow_negative, vbl_volume** out_volume)
{
    vbl_volume_load_options defaults = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    if (!path) path = "(memory)";
    if (!out_volume) {
        vbl_aligned_free(buffer);
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl_volume_create_from_nanovdb: out_volume is NULL", path);
    }
    *out_volume = NULL;
    if (!options) options = &defaults;
    vbl_result result = vbl_check_buffer(buffer, size, path);
    if (result != VBL_SUCCESS) {
        vbl_aligned_free(buffer);
        return result;
    }
    vbl_volume* v = calloc(1, sizeof *v);
    if (!v) {
        vbl_aligned_free(buffer);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    v->refcount = 1;
    v->nanovdb_buffer = buffer;
    v->nanovdb_size = size;
    v->buf = pnanovdb_make_buf((uint32_t*)buffer, size / 4);
    v->grid.address = pnanovdb_address_null();
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(v->buf, v->grid);
    v->root = pnanovdb_tree_get_root(v->buf, tree);

    vbl_volume_info* info = &v->info;
    info->size = sizeof *info;
    snprintf(info->file_path, sizeof info->file_path, "%s", path);
    const char* name = (const char*)buffer + PNANOVDB_GRID_OFF_GRID_NAME;
    const char* name_end = memchr(name, '\0', 255);
    size_t name_len = name_end ? (size_t)(name_end - name) : 255;
    memcpy(info->grid_name, name, name_len);
    info->grid_name[name_len] = '\0';
    info->grid_index = grid_index;
    vbl_set_transforms(v);

    vbl_scan scan;
    memset(&scan, 0, sizeof scan);
    scan.policy = options->bad_voxels;
    scan.allow_negative = allow_negative;
    scan.vmin = HUGE_VAL;
    scan.vmax = -HUGE_VAL;
    for (int a = 0; a < 3; ++a) {
        scan.bmin[a] = INT_MAX;
        scan.bmax[a] = INT_MIN;
    }
    vbl_scan_leaves(v, &scan, tree);
    vbl_scan_internal(v, &scan, tree, 1);
    vbl_scan_internal(v, &scan, tree, 2);
    vbl_scan_root(v, &scan);
    if (options->cancel && *options->cancel) {
        vbl_volume_destroy(v);
        return vbl_error(VBL_ERROR_INTERRUPTED, "%s: load cancelled (after the value scan)", path);
    }
    uint64_t bad = scan.bad_active + scan.bad_inactive;
    if (bad && options->bad_voxels != VBL_BAD_VOXELS_SANITIZE) {
        result = vbl_error(VBL_ERROR_BAD_VOXELS,
                           "%s: grid '%s' has %llu bad values (%llu NaN, %llu Inf, %llu negative; %llu active, %llu inactive); "
                           "load with the sanitize policy (vbl --sanitize) to set them to 0",
                           path, info->grid_name, (unsigned long long)bad, (unsigned long long)scan.bad_nan,
                           (unsigned long long)scan.bad_inf, (unsigned long long)scan.bad_negative,
                           (unsigned long long)scan.bad_active, (unsigned long long)scan.bad_inactive);
        vbl_volume_destroy(v); /* after formatting: the message reads info->grid_name */
        return result;
    }
    info->sanitized_voxels = bad;
    info->active_voxels = scan.active_voxels;
    if (scan.active_voxels) {
        for (int a = 0; a < 3; ++a) {
            info->index_bbox_min[a] = scan.bmin[a];
            info->index_bbox_max[a] = scan.bmax[a];
        }
        info->value_min = scan.vmin;
        info->value_max = scan.vmax;
        info->value_mean = scan.sum / (double)scan.active_voxels;
    } else {
        for (int a = 0; a < 3; ++a) {
            info->index_bbox_min[a] = 0;
            info->index_bbox_max[a] = -1;
        }
    }
    /* The root bbox is the one statistic the majorant grid reads (its values come from the voxels
     * themselves); make it the bbox we just measured so a stale file statistic cannot shrink it. */
    int32_t* root_bbox = (int32_t*)((char*)buffer + v->root.address.byte_offset + PNANOVDB_ROOT_OFF_BBOX_MIN);
    for (int a = 0; a < 3; ++a) {
        root_bbox[a] = scan.active_voxels ? scan.bmin[a] : INT_MAX;
        root_bbox[3 + a] = scan.active_voxels ? scan.bmax[a] : INT_MIN;
    }
    vbl_set_world_bbox(v);
    info->nanovdb_bytes = size;

    result = vbl_majorant_grid_build(&v->majorant, v, options->majorant_block_size);
    if (result == VBL_SUCCESS && options->cancel && *options->cancel)
        result = vbl_error(VBL_ERROR_INTERRUPTED, "%s: load cancelled (after the majorant grid)", path);
    if (result != VBL_SUCCESS) {
        vbl_volume_destroy(v);
        return result;
    }
    info->majorant_block_size = v->majorant.block;
    info->majorant_bytes = (uint64_t)v->majorant.dims[0] * (uint64_t)v->majorant.dims[1] * (uint64_t)v->majorant.dims[2] * 2u * sizeof(float);
    *out_volume = v;
    return VBL_SUCCESS;
}

VBL_API vbl_result vbl_volume_load(const char* path, const vbl_volume_load_options* options, vbl_volume** out_volume)
{
    vbl_volume_load_options defaults = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    if (out_volume) *out_volume = NULL;
    if (!path || !out_volume) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_volume_load: path and out_volume must not be NULL");
    if (!options) options = &defaults;
    if (options->size < sizeof(vbl_volume_load_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: vbl_volume_load_options.size = %zu, expected %zu", path, options->size,
                         sizeof(vbl_volume_load_options));
    if (options->bad_voxels != VBL_BAD_VOXELS_REJECT && options->bad_voxels != VBL_BAD_VOXELS_SANITIZE)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: unknown bad-voxel policy %d", path, (int)options->bad_voxels);
    /* The adapter dispatches on the file's magic number (OpenVDB or NanoVDB), not on its extension. */
    char message[2048];
    void* buffer = NULL;
    size_t size = 0;
    int file_index = -1;
    vbl_result result = vbl_vdb_read_float_grid(path, options->grid_name, options->grid_index, &buffer, &size, &file_index, message,
                                                sizeof message);
    if (result != VBL_SUCCESS) return vbl_error(result, "%s", message);
    if (options->cancel && *options->cancel) {
        vbl_aligned_free(buffer);
        return vbl_error(VBL_ERROR_INTERRUPTED, "%s: load cancelled (after reading the file)", path);
    }
    return vbl_volume_create_from_nanovdb(buffer, size, path, file_index, options, out_volume);
}

vbl_result vbl_volume_load_vec3_component(const char* path, const vbl_volume_load_options* options, int component,
                                          int allow_negative, vbl_volume** out_volume)
{
    vbl_volume_load_options defaults = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    if (out_volume) *out_volume = NULL;
    if (!path || !out_volume) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_volume_load_vec3_component: NULL argument");
    if (!options) options = &defaults;
    char message[2048];
    void* buffer = NULL;
    size_t size = 0;
    int file_index = -1;
    vbl_result result = vbl_vdb_read_vec3_component(path, options->grid_name, options->grid_index, component, &buffer,
                                                    &size, &file_index, message, sizeof message);
    if (result != VBL_SUCCESS) return vbl_error(result, "%s", message);
    return vbl_volume_create_signed(buffer, size, path, file_index, options, allow_negative, out_volume);
}

vbl_result vbl_volume_load_signed(const char* path, const vbl_volume_load_options* options, vbl_volume** out_volume)
{
    vbl_volume_load_options defaults = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    if (out_volume) *out_volume = NULL;
    if (!path || !out_volume) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_volume_load_signed: NULL argument");
    if (!options) options = &defaults;
    char message[2048];
    void* buffer = NULL;
    size_t size = 0;
    int file_index = -1;
    vbl_result result = vbl_vdb_read_float_grid(path, options->grid_name, options->grid_index, &buffer, &size, &file_index,
                                                message, sizeof message);
    if (result != VBL_SUCCESS) return vbl_error(result, "%s", message);
    return vbl_volume_create_signed(buffer, size, path, file_index, options, 1, out_volume);
}

VBL_API void vbl_volume_retain(vbl_volume* volume)
{
    if (volume) __atomic_fetch_add(&volume->refcount, 1, __ATOMIC_RELAXED);
}

VBL_API void vbl_volume_release(vbl_volume* volume)
{
    if (volume && __atomic_sub_fetch(&volume->refcount, 1, __ATOMIC_ACQ_REL) == 0) vbl_volume_destroy(volume);
}

VBL_API vbl_result vbl_volume_get_info(const vbl_volume* volume, vbl_volume_info* out_info)
{
    if (!volume || !out_info) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_volume_get_info: NULL argument");
    size_t n = out_info->size;
    if (n == 0 || n > sizeof *out_info) n = sizeof *out_info;
    memcpy(out_info, &volume->info, n);
    out_info->size = n;
    return VBL_SUCCESS;
}

VBL_API vbl_result vbl_file_list_grids(const char* path, vbl_grid_description** out_grids, size_t* out_count)
{
    if (out_grids) *out_grids = NULL;
    if (out_count) *out_count = 0;
    if (!path || !out_grids || !out_count) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_file_list_grids: NULL argument");
    char message[2048];
    vbl_vdb_grid_desc* descs = NULL;
    size_t count = 0;
    vbl_result result = vbl_vdb_list_grids(path, &descs, &count, message, sizeof message);
    if (result != VBL_SUCCESS) return vbl_error(result, "%s", message);
    vbl_grid_description* grids = calloc(count ? count : 1, sizeof *grids);
    if (!grids) {
        free(descs);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    for (size_t i = 0; i < count; ++i) {
        memcpy(grids[i].name, descs[i].name, sizeof grids[i].name);
        memcpy(grids[i].type, descs[i].type, sizeof grids[i].type);
        memcpy(grids[i].codec, descs[i].codec, sizeof grids[i].codec);
        grids[i].is_float = descs[i].is_float;
        grids[i].active_voxels = descs[i].active_voxels;
        for (int a = 0; a < 3; ++a) {
            grids[i].index_bbox_min[a] = descs[i].index_bbox_min[a];
            grids[i].index_bbox_max[a] = descs[i].index_bbox_max[a];
            grids[i].voxel_size[a] = descs[i].voxel_size[a];
        }
    }
    free(descs);
    *out_grids = grids;
    *out_count = count;
    return VBL_SUCCESS;
}

VBL_API void vbl_grid_descriptions_free(vbl_grid_description* grids) { free(grids); }
