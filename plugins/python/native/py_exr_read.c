/* EXR files read for Python (vbl_python_native.h): the channels and header attributes of a file
 * `vbl render` (or anything else) wrote, through the project's reader (vbl_exr.h). */
#include "vbl_exr.h"
#include "vbl_python_native.h"

vbl_result vbl_py_exr_open(const char* path, vbl_py_exr** out) { return vbl_exr_read(path, (vbl_exr_image**)out); }
void vbl_py_exr_close(vbl_py_exr* file) { vbl_exr_image_release((vbl_exr_image*)file); }
int vbl_py_exr_width(const vbl_py_exr* file) { return vbl_exr_image_width((const vbl_exr_image*)file); }
int vbl_py_exr_height(const vbl_py_exr* file) { return vbl_exr_image_height((const vbl_exr_image*)file); }
int vbl_py_exr_channel_count(const vbl_py_exr* file) { return vbl_exr_image_channel_count((const vbl_exr_image*)file); }

const char* vbl_py_exr_channel_name(const vbl_py_exr* file, int index)
{
    return vbl_exr_image_channel_name((const vbl_exr_image*)file, index);
}

const float* vbl_py_exr_channel_pixels(const vbl_py_exr* file, int index)
{
    return vbl_exr_image_channel_pixels((const vbl_exr_image*)file, index);
}

int vbl_py_exr_attribute_count(const vbl_py_exr* file)
{
    return vbl_exr_image_attribute_count((const vbl_exr_image*)file);
}

const char* vbl_py_exr_attribute_name(const vbl_py_exr* file, int index)
{
    return vbl_exr_image_attribute_name((const vbl_exr_image*)file, index);
}

const char* vbl_py_exr_attribute(const vbl_py_exr* file, const char* name, int* type)
{
    return vbl_exr_image_attribute((const vbl_exr_image*)file, name, type);
}
