/* vbl_render_resume (vbl/vbl_film.h): a checkpoint film continued to all its passes, in the library
 * so that C and Python callers resume as `vbl render --resume` does (render the passes left with
 * the single render's seeds, then merge by pass count). */
#include <string.h>

#include "core/error.h"
#include "vbl/vbl_film.h"

vbl_result vbl_render_resume(const vbl_scene* scene, const vbl_render_options* options, const vbl_film* base,
                             vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    if (!scene || !options || !base || !out_film)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_resume: NULL argument");
    vbl_result r = vbl_render_options_validate(options);
    if (r) return r;
    vbl_film_stats b;
    memset(&b, 0, sizeof b);
    b.size = sizeof b;
    if ((r = vbl_film_get_stats(base, &b))) return r;
    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    if (vbl_film_width(base) != w || vbl_film_height(base) != h)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_resume: the base film is %dx%d, the scene %dx%d",
                         vbl_film_width(base), vbl_film_height(base), w, h);
    const int light_paths = vbl_render_light_paths(scene, options);
    if (b.method != options->method || b.spp != options->spp || b.light_paths != light_paths ||
        b.seed != options->seed)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "vbl_render_resume: the base film is another render (method %s / %s, spp %d / %d, light "
                         "paths %d / %d, seed %llu / %llu)",
                         vbl_render_method_name(b.method), vbl_render_method_name(options->method), b.spp, options->spp,
                         b.light_paths, light_paths, (unsigned long long)b.seed,
                         (unsigned long long)options->seed);
    if (b.first_pass != options->first_pass)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "vbl_render_resume: the base film starts at pass %d, the options at pass %d", b.first_pass,
                         options->first_pass);
    if (b.passes >= options->passes) {
        vbl_film_retain((vbl_film*)base);
        *out_film = (vbl_film*)base;
        return VBL_SUCCESS;
    }
    vbl_render_options rest = *options;
    rest.size = sizeof rest;
    rest.first_pass = options->first_pass + b.passes;
    rest.passes = options->passes - b.passes;
    vbl_film* more = NULL;
    r = vbl_render(scene, &rest, &more);
    if (r && !(r == VBL_ERROR_INTERRUPTED && more)) return r;
    vbl_result rendered = r;
    const vbl_film* films[2] = {base, more};
    r = vbl_film_merge(films, 2, out_film);
    vbl_film_release(more);
    if (r) return r;
    return rendered == VBL_ERROR_INTERRUPTED ? vbl_error(VBL_ERROR_INTERRUPTED, "vbl_render_resume: stopped by the callback")
                                            : VBL_SUCCESS;
}
