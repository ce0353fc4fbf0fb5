/* Prints "struct size" and "struct.field offset" lines for the public structs the Python binding
 * mirrors with ctypes (tests/pipeline/test_python.py compares them with ctypes.sizeof/offset). */
#include <stddef.h>
#include <stdio.h>

#include <vbl/vbl.h>

#define SIZE(T) printf("%s %zu\n", #T, sizeof(T))
#define OFF(T, f) printf("%s.%s %zu\n", #T, #f, offsetof(T, f))

int main(void)
{
    SIZE(vbl_volume_load_options);
    SIZE(vbl_volume_info);
    OFF(vbl_volume_info, sanitized_voxels);
    OFF(vbl_volume_info, index_to_world);
    SIZE(vbl_transmittance_options);
    SIZE(vbl_transmittance_result);
    SIZE(vbl_scene_load_options);
    OFF(vbl_scene_load_options, frame);
    OFF(vbl_scene_load_options, use_frame);
    SIZE(vbl_render_progress);
    SIZE(vbl_render_options);
    OFF(vbl_render_options, method);
    OFF(vbl_render_options, passes);
    OFF(vbl_render_options, spp);
    OFF(vbl_render_options, light_paths);
    OFF(vbl_render_options, seed);
    OFF(vbl_render_options, time_limit);
    OFF(vbl_render_options, threads);
    OFF(vbl_render_options, max_bounces);
    OFF(vbl_render_options, transmittance);
    OFF(vbl_render_options, mis);
    OFF(vbl_render_options, callback);
    OFF(vbl_render_options, callback_user_data);
    OFF(vbl_render_options, vrl_samples);
    OFF(vbl_render_options, vrl_long);
    OFF(vbl_render_options, vrl_connect_march);
    OFF(vbl_render_options, vrl_march_step);
    OFF(vbl_render_options, vrl_prune_radius);
    OFF(vbl_render_options, vrl_prune_min_probability);
    OFF(vbl_render_options, vpl_clamp_distance);
    OFF(vbl_render_options, vbl_radius0);
    OFF(vbl_render_options, vbl_alpha);
    OFF(vbl_render_options, first_pass);
    OFF(vbl_render_options, vbl_single_scattering);
    OFF(vbl_render_options, beams_radius0);
    OFF(vbl_render_options, beams_alpha);
    OFF(vbl_render_options, vsl_placement);
    OFF(vbl_render_options, vsl_path_extension);
    OFF(vbl_render_options, vsl_lights);
    SIZE(vbl_film_stats);
    OFF(vbl_film_stats, time_limited);
    OFF(vbl_film_stats, first_pass);
    return 0;
}
