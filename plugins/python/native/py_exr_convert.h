/* Colour conversion of film layers for Film.write_exr (py_exr_convert.c); internal to libvbl_python. */
#ifndef VBL_PY_EXR_CONVERT_H
#define VBL_PY_EXR_CONVERT_H

#include <stddef.h>

#include "vbl_color.h"
#include "vbl_python_native.h"

/* The config of a vbl_py_color (py_color.c). */
const vbl_color_config* vbl_py_color_config(const vbl_py_color* color);
/* scene_linear -> output_space as a row-major 3x3 matrix; VBL_ERROR_INVALID_ARGUMENT if the
 * space is not linear. */
vbl_result vbl_py_color_matrix(const vbl_py_color* color, const char* output_space, double m[9]);
/* A converted copy of n pixels of `channels` floats (RGB times m, or times m squared element-wise
 * for a variance); other channels copied. NULL when out of memory. */
float* vbl_py_convert_layer(const float* pixels, size_t n, int channels, const double m[9], int variance);
/* beauty RGB = the sum of the transport layers in the given (film) order, in float. */
void vbl_py_resum_beauty(float* beauty, int beauty_channels, const float* const* transport,
                         const int* transport_channels, int transport_count, size_t n);

#endif
