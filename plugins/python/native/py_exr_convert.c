/* Film layers converted to an output colour space for Film.write_exr(output_space=...), as
 * `vbl render --output-space` converts them (plugins/cli/render_output.c): the scene_linear ->
 * output matrix read off the OCIO conversion of the unit vectors (the space must be linear),
 * RGB of colour layers times the matrix, variances times its element-wise square, and the
 * beauty re-summed from the converted transport layers in film order so the layers still sum to
 * it exactly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "py_exr_convert.h"
#include "vbl_color.h"

vbl_result vbl_py_color_matrix(const vbl_py_color* color, const char* output_space, double m[9])
{
    const vbl_color_config* config = vbl_py_color_config(color);
    const char* scene = vbl_py_color_scene_space(color);
    for (int c = 0; c < 3; ++c) {
        float e[3] = {0.0f, 0.0f, 0.0f};
        e[c] = 1.0f;
        vbl_result r = vbl_color_convert_rgb(config, scene, output_space, e);
        if (r) return r;
        for (int k = 0; k < 3; ++k) m[3 * k + c] = e[k];
    }
    static const float probes[2][3] = {{0.02f, 0.5f, 3.0f}, {40.0f, 0.25f, 0.125f}};
    for (int p = 0; p < 2; ++p) {
        float v[3] = {probes[p][0], probes[p][1], probes[p][2]};
        vbl_result r = vbl_color_convert_rgb(config, scene, output_space, v);
        if (r) return r;
        for (int k = 0; k < 3; ++k) {
            double want = m[3 * k] * probes[p][0] + m[3 * k + 1] * probes[p][1] + m[3 * k + 2] * probes[p][2];
            if (!(fabs(want - v[k]) <= 1e-4 * (1.0 + fabs(want))))
                return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT,
                                        "output_space '%s' is not a scene-linear colour space (the EXR holds linear "
                                        "radiance)", output_space);
        }
    }
    return VBL_SUCCESS;
}

float* vbl_py_convert_layer(const float* pixels, size_t n, int channels, const double m[9], int variance)
{
    float* copy = malloc(sizeof(float) * (n ? n : 1) * (size_t)channels);
    if (!copy) return NULL;
    memcpy(copy, pixels, sizeof(float) * n * (size_t)channels);
    double mm[9];
    for (int e = 0; e < 9; ++e) mm[e] = variance ? m[e] * m[e] : m[e];
    for (size_t p = 0; p < n; ++p) {
        float* v = copy + p * (size_t)channels;
        double x = v[0], y = v[1], z = v[2];
        for (int r = 0; r < 3; ++r) v[r] = (float)(mm[3 * r] * x + mm[3 * r + 1] * y + mm[3 * r + 2] * z);
    }
    return copy;
}

void vbl_py_resum_beauty(float* beauty, int beauty_channels, const float* const* transport,
                         const int* transport_channels, int transport_count, size_t n)
{
    for (size_t p = 0; p < n; ++p) {
        float sum[3] = {0.0f, 0.0f, 0.0f};
        for (int k = 0; k < transport_count; ++k)
            for (int c = 0; c < 3; ++c) sum[c] += transport[k][p * (size_t)transport_channels[k] + (size_t)c];
        for (int c = 0; c < 3; ++c) beauty[p * (size_t)beauty_channels + (size_t)c] = sum[c];
    }
}
