/* Caustic photon map: hash grid and the progressive photon mapping gather (surface_caustics.h). */
#include "transport/surface/surface_caustics.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#define VBL_CAUSTIC_MAX_CELLS 64 /* query cells beyond which a linear scan is used */

int vbl_material_is_highly_specular(const vbl_material* m)
{
    switch (m->type) {
    case VBL_MATERIAL_PHONG:
        return vbl_v3_max_component(m->specular) > 0.0 && m->exponent >= VBL_HIGHLY_SPECULAR_PHONG_EXPONENT;
    case VBL_MATERIAL_GGX: return m->roughness <= VBL_HIGHLY_SPECULAR_GGX_ROUGHNESS;
    default: return 0;
    }
}

int vbl_materials_any_highly_specular(const vbl_material* materials, int count)
{
    for (int i = 0; i < count; ++i)
        if (vbl_material_is_highly_specular(&materials[i])) return 1;
    return 0;
}

/* Cell coordinate, clamped so that the conversion is defined for any finite or huge value. */
static int64_t vbl_cell_coord(double v, double cell)
{
    double c = floor(v / cell);
    if (!(c > -4e18)) c = -4e18;
    if (c > 4e18) c = 4e18;
    return (int64_t)c;
}

static size_t vbl_cell_hash(int64_t ix, int64_t iy, int64_t iz, size_t table_size)
{
    uint64_t h = (uint64_t)ix * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)iy * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= (uint64_t)iz * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    h ^= h >> 29;
    return (size_t)(h & (uint64_t)(table_size - 1));
}

static size_t vbl_photon_bucket(const vbl_caustic_map* map, vbl_vec3 p)
{
    return vbl_cell_hash(vbl_cell_coord(p.x, map->cell), vbl_cell_coord(p.y, map->cell),
                         vbl_cell_coord(p.z, map->cell), map->table_size);
}

vbl_result vbl_caustic_map_build(vbl_caustic_map* map, const vbl_caustic_photon* photons, size_t count, double cell)
{
    memset(map, 0, sizeof *map);
    if (count == 0) return VBL_SUCCESS;
    if (!(cell > 0.0) || !isfinite(cell))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "caustic map: cell = %g must be finite and > 0", cell);
    size_t size = 16;
    while (size < 2 * count) size *= 2;
    map->photons = malloc(count * sizeof *map->photons);
    map->start = calloc(size + 1, sizeof *map->start);
    size_t* bucket = malloc(count * sizeof *bucket);
    if (!map->photons || !map->start || !bucket) {
        free(bucket);
        vbl_caustic_map_free(map);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "caustic map: out of memory for %zu photons", count);
    }
    map->count = count;
    map->table_size = size;
    map->cell = cell;
    /* counting sort by bucket (stable: the order within a bucket is the input order) */
    for (size_t i = 0; i < count; ++i) {
        bucket[i] = vbl_photon_bucket(map, photons[i].position);
        ++map->start[bucket[i] + 1];
    }
    for (size_t b = 0; b < size; ++b) map->start[b + 1] += map->start[b];
    size_t* fill = malloc(size * sizeof *fill);
    if (!fill) {
        free(bucket);
        vbl_caustic_map_free(map);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "caustic map: out of memory for %zu photons", count);
    }
    memcpy(fill, map->start, size * sizeof *fill);
    for (size_t i = 0; i < count; ++i) map->photons[fill[bucket[i]]++] = photons[i];
    free(fill);
    free(bucket);
    return VBL_SUCCESS;
}

void vbl_caustic_map_free(vbl_caustic_map* map)
{
    if (!map) return;
    free(map->photons);
    free(map->start);
    memset(map, 0, sizeof *map);
}

double vbl_caustic_kernel(double dist2, double radius)
{
    if (!(radius > 1e-100)) return 0.0; /* no representable disc area left */
    double r2 = radius * radius;
    if (!(dist2 < r2)) return 0.0;
    return 2.0 / (VBL_PI * r2) * (1.0 - dist2 / r2);
}

/* f(wo, wi) Phi K_R of one photon (0 when it lies outside the disc or on the other side). */
static vbl_vec3 vbl_caustic_one(const vbl_caustic_photon* p, vbl_vec3 x, vbl_vec3 n, vbl_vec3 wo,
                                const vbl_material* m, double radius, int max_bounces)
{
    vbl_vec3 zero = vbl_v3(0.0, 0.0, 0.0);
    if (max_bounces >= 0 && p->bounce + 1 > max_bounces) return zero;
    vbl_vec3 to = vbl_v3_sub(p->position, x);
    double k = vbl_caustic_kernel(vbl_v3_dot(to, to), radius);
    if (!(k > 0.0) || !(vbl_v3_dot(p->normal, n) > 0.5) || !(vbl_v3_dot(p->incident, n) > 0.0)) return zero;
    vbl_vec3 f = vbl_material_eval(m, n, wo, p->incident);
    return vbl_v3_scale(vbl_v3_mul(f, p->power), k);
}

vbl_vec3 vbl_caustic_gather(const vbl_caustic_map* map, vbl_vec3 x, vbl_vec3 n, vbl_vec3 wo, const vbl_material* m,
                            double radius, int max_bounces)
{
    vbl_vec3 sum = vbl_v3(0.0, 0.0, 0.0);
    if (!map || map->count == 0 || !(radius > 1e-100) || !isfinite(radius)) return sum;
    const double c = map->cell;
    int64_t lo[3] = {vbl_cell_coord(x.x - radius, c), vbl_cell_coord(x.y - radius, c), vbl_cell_coord(x.z - radius, c)};
    int64_t hi[3] = {vbl_cell_coord(x.x + radius, c), vbl_cell_coord(x.y + radius, c), vbl_cell_coord(x.z + radius, c)};
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) cells *= (double)(hi[a] - lo[a]) + 1.0;
    if (!(cells <= VBL_CAUSTIC_MAX_CELLS)) { /* radius much larger than the cells: scan */
        for (size_t i = 0; i < map->count; ++i)
            sum = vbl_v3_add(sum, vbl_caustic_one(&map->photons[i], x, n, wo, m, radius, max_bounces));
        return sum;
    }
    size_t seen[VBL_CAUSTIC_MAX_CELLS];
    int nseen = 0;
    for (int64_t ix = lo[0]; ix <= hi[0]; ++ix)
        for (int64_t iy = lo[1]; iy <= hi[1]; ++iy)
            for (int64_t iz = lo[2]; iz <= hi[2]; ++iz) {
                size_t b = vbl_cell_hash(ix, iy, iz, map->table_size);
                int dup = 0; /* two cells hashed to one bucket: visit it once */
                for (int s = 0; s < nseen && !dup; ++s) dup = seen[s] == b;
                if (dup) continue;
                seen[nseen++] = b;
                for (size_t i = map->start[b]; i < map->start[b + 1]; ++i)
                    sum = vbl_v3_add(sum, vbl_caustic_one(&map->photons[i], x, n, wo, m, radius, max_bounces));
            }
    return sum;
}

double vbl_caustic_default_r0(const vbl_caustic_photon* photons, size_t count, vbl_vec3 lo, vbl_vec3 hi)
{
    double diag = vbl_v3_length(vbl_v3_sub(hi, lo));
    if (!(diag > 0.0) || !isfinite(diag)) return 0.0;
    if (count < 2) return 0.01 * diag;
    vbl_vec3 a = photons[0].position, b = photons[0].position;
    for (size_t i = 1; i < count; ++i) {
        vbl_vec3 p = photons[i].position;
        a = vbl_v3(fmin(a.x, p.x), fmin(a.y, p.y), fmin(a.z, p.z));
        b = vbl_v3(fmax(b.x, p.x), fmax(b.y, p.y), fmax(b.z, p.z));
    }
    vbl_vec3 e = vbl_v3_sub(b, a);
    double area = e.x * e.y + e.y * e.z + e.z * e.x;
    double r0 = area > 0.0 ? sqrt(10.0 * area / (VBL_PI * (double)count)) : 0.0;
    if (!(r0 >= 1e-3 * diag)) r0 = 1e-3 * diag;
    if (r0 > 0.05 * diag) r0 = 0.05 * diag;
    return r0;
}
