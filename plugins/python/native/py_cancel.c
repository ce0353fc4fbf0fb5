/* The cancel flag of a render from Python (vbl_python_native.h). */
#include "vbl_python_native.h"

void vbl_py_options_set_cancel(vbl_render_options* options, const volatile int* flag)
{
    if (options) options->cancel = flag;
}
