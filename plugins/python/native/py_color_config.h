/* The OCIO config of a vbl_py_color (py_color.c), for py_exr.c; internal to libvbl_python. */
#ifndef VBL_PY_COLOR_CONFIG_H
#define VBL_PY_COLOR_CONFIG_H

#include "vbl_color.h"
#include "vbl_python_native.h"

const vbl_color_config* vbl_py_color_config(const vbl_py_color* color);

#endif
