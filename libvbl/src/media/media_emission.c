/* Emissive media: Le from an emission grid and/or a temperature grid (blackbody). */
#include "media/media_emission.h"

#include <math.h>

#include "core/error.h"
#include "media/medium_grids.h"

void vbl_emission_cursor_init(vbl_emission_cursor* cursor, const vbl_scene* scene)
{
    cursor->time = 0.0;
    for (int i = 0; i < scene->media_count; ++i) {
        const vbl_medium* m = &scene->media[i];
        if (m->emission_volume) vbl_grid_accessor_init(&cursor->emission[i], m->emission_volume);
        if (m->temperature_volume) vbl_grid_accessor_init(&cursor->temperature[i], m->temperature_volume);
    }
}

vbl_vec3 vbl_medium_le(const vbl_scene* scene, vbl_emission_cursor* cursor, int i, vbl_vec3 p)
{
    const vbl_medium* m = &scene->media[i];
    vbl_vec3 le = vbl_v3(0.0, 0.0, 0.0);
    vbl_vec3 q = vbl_medium_grid_point(scene, i, p, cursor->time);
    if (m->emission_volume) {
        double e = vbl_grid_sample_world(&cursor->emission[i], q, VBL_FILTER_TRILINEAR);
        if (e > 0.0) le = vbl_v3_scale(m->emission_color, m->emission_scale * e);
    }
    if (m->temperature_volume) {
        double t = vbl_grid_sample_world(&cursor->temperature[i], q, VBL_FILTER_TRILINEAR);
        double kelvin = t * m->temperature_scale + m->temperature_offset;
        if (kelvin > 0.0)
            le = vbl_v3_madd(le, vbl_blackbody_table_rgb(&m->blackbody, kelvin), m->blackbody_intensity);
    }
    return le;
}

vbl_vec3 vbl_media_emission(const vbl_scene* scene, vbl_emission_cursor* cursor, vbl_vec3 p,
                            const double* component_sigma_t)
{
    vbl_vec3 sum = vbl_v3(0.0, 0.0, 0.0);
    for (int i = 0; i < scene->media_count; ++i) {
        const vbl_medium* m = &scene->media[i];
        double st = component_sigma_t[i];
        if (!m->emissive || !(st > 0.0)) continue;
        vbl_vec3 le = vbl_medium_le(scene, cursor, i, p);
        const vbl_vec3 a = m->albedo_volume[0] ? vbl_medium_albedo_at(scene, i, p, cursor->time) : m->albedo;
        sum.x += st * (1.0 - a.x) * le.x;
        sum.y += st * (1.0 - a.y) * le.y;
        sum.z += st * (1.0 - a.z) * le.z;
    }
    return sum;
}

static int vbl_finite_nonneg(double v) { return isfinite(v) && v >= 0.0; }

vbl_result vbl_scene_set_medium_emission(vbl_scene* scene, int index, vbl_volume* emission, vbl_vec3 color,
                                         double scale, vbl_volume* temperature, double temperature_scale,
                                         double temperature_offset, double blackbody_intensity,
                                         vbl_blackbody_normalization norm)
{
    if (!scene || index < 0 || index >= scene->media_count)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "emission: no medium %d", index);
    if (!vbl_finite_nonneg(color.x) || !vbl_finite_nonneg(color.y) || !vbl_finite_nonneg(color.z) ||
        !vbl_finite_nonneg(scale) || !vbl_finite_nonneg(blackbody_intensity) || !isfinite(temperature_scale) ||
        !isfinite(temperature_offset))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "%s: media[%d]: emission colour, scale and blackbody intensity must be finite and >= 0, "
                         "temperature scale and offset finite",
                         scene->path, index);
    vbl_medium* m = &scene->media[index];
    if (temperature && !m->blackbody.rgb && !vbl_blackbody_table_build(&m->blackbody, norm))
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: media[%d]: out of memory for the blackbody table", scene->path,
                         index);
    if (emission) vbl_volume_retain(emission);
    if (temperature) vbl_volume_retain(temperature);
    if (m->emission_volume) vbl_volume_release(m->emission_volume);
    if (m->temperature_volume) vbl_volume_release(m->temperature_volume);
    m->emission_volume = emission;
    m->emission_color = color;
    m->emission_scale = scale;
    m->temperature_volume = temperature;
    m->temperature_scale = temperature_scale;
    m->temperature_offset = temperature_offset;
    m->blackbody_intensity = blackbody_intensity;
    const vbl_vec3 amin = m->albedo_volume[0] ? m->albedo_min : m->albedo; /* the least albedo anywhere */
    int absorbs = amin.x < 1.0 || amin.y < 1.0 || amin.z < 1.0;
    m->emissive = absorbs && ((emission && scale > 0.0 && vbl_v3_max_component(color) > 0.0) ||
                              (temperature && blackbody_intensity > 0.0));
    scene->has_emission = 0;
    for (int i = 0; i < scene->media_count; ++i) scene->has_emission |= scene->media[i].emissive;
    scene->emission_nee = 1;
    return vbl_emission_lights_build(&scene->emission_lights, scene);
}
