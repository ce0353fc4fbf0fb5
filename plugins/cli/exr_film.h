/* vbl renders read back from EXR as films (vbl/vbl_film.h), so that `vbl merge` and `vbl render
 * --resume` combine them with the library's vbl_film_merge. */
#ifndef VBL_CLI_EXR_FILM_H
#define VBL_CLI_EXR_FILM_H

#include <stddef.h>

#include <vbl/vbl.h>

#include "vbl_exr.h"

/* The film of an EXR written by `vbl render`: the beauty R,G,B,A as layer "", "Z", and one layer per
 * "name.X" channel prefix (channels in R, G, B, A, Y order); stats from vbl:method, vbl:spp,
 * vbl:light_paths, vbl:seed, vbl:passes, vbl:first_pass, vbl:render_seconds (passes: `passes`
 * when >= 1 overrides the file's). Errors name the file. */
vbl_result vbl_cli_film_from_exr(const vbl_exr_image* image, const char* path, int passes, vbl_film** out_film);
/* Channel `name` of the file's naming ("R", "Z", "emission.G") in the film, as a planar copy into
 * out[n]; 0 if the film has no such channel. */
int vbl_cli_film_channel(const vbl_film* film, const char* name, float* out, size_t n);

#endif
