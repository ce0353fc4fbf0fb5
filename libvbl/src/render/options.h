/* The render options table's checked assignments (vbl/vbl_render_options.h), shared by the
 * library's validator, the public set/get calls and the scene file's `render` block
 * (scene/scene_render_block.c). */
#ifndef VBL_RENDER_OPTIONS_INTERNAL_H
#define VBL_RENDER_OPTIONS_INTERNAL_H

#include <stddef.h>

#include "vbl/vbl_render.h"

/* Option indices in table order: VBL_OPT_method, VBL_OPT_passes, ... */
#define VBL_OPT_INDEX_(prefix, name, ...) VBL_OPT_##name,
#define VBL_OPT_SKIP_(prefix, member, ctype, def)
enum { VBL_RENDER_OPTION_LIST(VBL_OPT_INDEX_, VBL_OPT_SKIP_) VBL_OPT_COUNT };

/* On failure the check and assign calls write the reason as it follows the option's name in a
 * message ("= 1 is outside (0, 1)", "= \"x\" is not one of a, b", "must be an integer") into
 * why[size] and return non-zero. `strict` (scene files, CLI): also refuse the 0 of
 * VBL_OPTION_ZERO_DEFAULT options. */
int vbl_option_check_number(int index, double value, int strict, char* why, size_t size);
/* Assigns a number (integral for int, bool and enum options) after the check. */
int vbl_option_assign_number(vbl_render_options* o, int index, double value, int strict, char* why, size_t size);
/* Assigns from text (vbl_render_option_set's syntax). */
int vbl_option_assign_text(vbl_render_options* o, int index, const char* text, int strict, char* why, size_t size);
/* An enum option's value of `name`, or -1 (strict: not its ZERO_DEFAULT choice 0). */
int vbl_option_enum_value(int index, const char* name, int strict);
/* The value as a number (uint64 rounded to double). */
double vbl_option_number(const vbl_render_options* o, int index);

#endif
