/* Prints "struct size" and "struct.field offset" lines for the public structs the Python binding
 * mirrors with ctypes (tests/pipeline/test_python.py compares them with ctypes.sizeof/offset). */
#include <stddef.h>
#include <stdio.h>

#include <vbl/vbl.h>

#ifdef VBL_ABI_NATIVE
#include "vbl_python_native.h" /* libvbl_python: the package's C side */
#endif

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
    /* vbl_render_options is not mirrored: the binding goes through vbl_render_option_set/get. */
    SIZE(vbl_render_option_info);
    OFF(vbl_render_option_info, type);
    OFF(vbl_render_option_info, default_value);
    OFF(vbl_render_option_info, flags);
    OFF(vbl_render_option_info, choices);
    OFF(vbl_render_option_info, effect);
    OFF(vbl_render_option_info, help);
    SIZE(vbl_film_stats);
    OFF(vbl_film_stats, time_limited);
    OFF(vbl_film_stats, first_pass);
    OFF(vbl_film_stats, discarded_pass);
#ifdef VBL_ABI_NATIVE
    SIZE(vbl_py_exr_options);
    OFF(vbl_py_exr_options, passes_requested);
    OFF(vbl_py_exr_options, half_layers);
    OFF(vbl_py_exr_options, aov_variance);
    OFF(vbl_py_exr_options, color);
    OFF(vbl_py_exr_options, output_space);
#endif
    return 0;
}
