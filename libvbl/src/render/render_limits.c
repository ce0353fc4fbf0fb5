/* The documented limits of the estimators at the extremes (render_limits.h, vbl_render_limits). */
#include "render/render_limits.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "transport/common/light_emission.h"

double vbl_limits_media_diameter(const vbl_scene* scene)
{
    vbl_vec3 c;
    double r = 0.0;
    if (!scene || !vbl_media_bounding_sphere(scene, &c, &r) || !(r > 0.0) || !isfinite(r)) return 0.0;
    return 2.0 * r;
}

static int vbl_limits_uses_beams_radius(const char* method, const vbl_render_options* o)
{
    return strcmp(method, "beams") == 0 ||
           (strcmp(method, "vbl") == 0 && o->beam_lights.single_scattering == VBL_SINGLE_SCATTERING_BEAMS);
}

vbl_result vbl_limits_check_radius(const vbl_scene* scene, const vbl_render_options* options, const char* method)
{
    if (!(options->beams.radius0 > 0.0) || !vbl_limits_uses_beams_radius(method, options)) return VBL_SUCCESS;
    double d = vbl_limits_media_diameter(scene);
    if (!(d > 0.0) || options->beams.radius0 >= VBL_LIMIT_BEAMS_RADIUS_MIN * d) return VBL_SUCCESS;
    return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                     "%s: beams.radius0 = %g is below %g x the media's size (%g): beams this narrow are never "
                     "found by a camera ray (the image would be black); use at least %g or 0 for the default",
                     scene->path, options->beams.radius0, VBL_LIMIT_BEAMS_RADIUS_MIN, d,
                     VBL_LIMIT_BEAMS_RADIUS_MIN * d);
}

typedef struct vbl_limits_out {
    char* buf;
    size_t size, used;
    int count;
} vbl_limits_out;

static void vbl_limits_add(vbl_limits_out* out, const char* fmt, ...)
{
    ++out->count;
    if (!out->buf || out->used + 1 >= out->size) return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(out->buf + out->used, out->size - out->used, fmt, ap);
    va_end(ap);
    if (n < 0) return;
    out->used += (size_t)n < out->size - out->used ? (size_t)n : out->size - out->used - 1;
    if (out->used + 1 < out->size) {
        out->buf[out->used++] = '\n';
        out->buf[out->used] = '\0';
    }
}

int vbl_render_limits(const vbl_scene* scene, const vbl_render_options* options, char* message, size_t size)
{
    vbl_limits_out out = {message, size, 0, 0};
    if (message && size > 0) message[0] = '\0';
    if (!scene || !options) return 0;
    const vbl_render_method m = options->method;
    if (m == VBL_RENDER_PT) return 0;
    const char* name = vbl_render_method_name(m);
    for (int i = 0; i < scene->media_count; ++i)
        if (fabs(scene->media[i].g) > VBL_LIMIT_CONNECT_G)
            vbl_limits_add(&out,
                           "%s: media[%d] phase g = %g: above |g| = %g method '%s' connects light and camera points "
                           "through a near-delta phase lobe it almost never hits, so multiple scattering comes out "
                           "near 0 (use method pt)",
                           scene->path, i, scene->media[i].g, VBL_LIMIT_CONNECT_G, name);
    const double d = vbl_limits_media_diameter(scene);
    if (d > 0.0) {
        if (vbl_limits_uses_beams_radius(name, options) && options->beams.radius0 > VBL_LIMIT_RADIUS_MAX * d)
            vbl_limits_add(&out,
                           "%s: beams.radius0 = %g is above %g x the media's size (%g): the beam kernel blurs light "
                           "into empty space and the image loses energy",
                           scene->path, options->beams.radius0, VBL_LIMIT_RADIUS_MAX, d);
        if (m == VBL_RENDER_VBL && options->beam_lights.radius0 > VBL_LIMIT_RADIUS_MAX * d)
            vbl_limits_add(&out,
                           "%s: vbl.radius0 = %g is above %g x the media's size (%g): virtual beam lights this wide "
                           "lose multiple scattering (volume_from_volume)",
                           scene->path, options->beam_lights.radius0, VBL_LIMIT_RADIUS_MAX, d);
        const double sigma = scene->extinction.max_sigma_t;
        const int beams = vbl_limits_uses_beams_radius(name, options);
        const double r_beams = options->beams.radius0 > 0.0 ? options->beams.radius0 : VBL_LIMIT_DEFAULT_RADIUS_MIN * d;
        const double r_vbl =
            options->beam_lights.radius0 > 0.0 ? options->beam_lights.radius0 : VBL_LIMIT_DEFAULT_RADIUS_MIN * d;
        const double r = m == VBL_RENDER_VBL ? (beams ? fmin(r_beams, r_vbl) : r_vbl) : r_beams;
        if ((beams || m == VBL_RENDER_VBL) && r * sigma > VBL_LIMIT_THICK_RADIUS_MFP)
            vbl_limits_add(&out,
                           "%s: the media are optically thick for method '%s' (sigma_t up to %g): its kernel radius "
                           "(at least %g) spans %.3g mean free paths, so light is blurred between lit and unlit "
                           "depths and the image comes out too dark (use pt or vrl)",
                           scene->path, name, sigma, r, r * sigma);
        if (m == VBL_RENDER_VPL && sigma * d > VBL_LIMIT_THICK_VPL_MFP)
            vbl_limits_add(&out,
                           "%s: the media are optically thick for method 'vpl' (sigma_t up to %g, %.3g mean free "
                           "paths across): only a thin skin is lit and its virtual point lights are rarely reached "
                           "from the camera rays, so a finite render comes out too dark (use pt or vrl)",
                           scene->path, sigma, sigma * d);
    }
    return out.count;
}
