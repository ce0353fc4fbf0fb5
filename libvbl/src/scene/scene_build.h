/* Affine helpers for scene building (the programmatic API itself is in scene/scene.h). */
#ifndef VBL_SCENE_SCENE_BUILD_H
#define VBL_SCENE_SCENE_BUILD_H

#include "core/math.h"

/* Inverse of an affine map; returns 0 if it is singular (relative determinant < 1e-12). */
int vbl_affine_invert(const vbl_affine* a, vbl_affine* out);
void vbl_affine_set_identity(vbl_affine* a);

#endif
