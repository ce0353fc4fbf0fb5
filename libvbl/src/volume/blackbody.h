/* Blackbody emission colours: Planck's law integrated against the CIE 1931 2-degree colour
 * matching functions, converted to linear Rec.709 (D65), the default scene_linear space
 * (docs/readme/emission.md). */
#ifndef VBL_VOLUME_BLACKBODY_H
#define VBL_VOLUME_BLACKBODY_H

#include "core/math.h"

/* How the colour of temperature T is scaled (docs/readme/emission.md "Blackbody"). */
typedef enum vbl_blackbody_normalization {
    VBL_BLACKBODY_PEAK = 0,     /* pbrt-v4: the spectrum divided by its value at Wien's peak, XYZ
                                   divided by the integral of ybar (cold media are dark) */
    VBL_BLACKBODY_LUMINANCE = 1 /* Cycles' Blackbody node: the colour with luminance Y = 1 */
} vbl_blackbody_normalization;

/* CIE 1931 2-degree colour matching functions at wavelength `nm` (tabulated, linearly interpolated). */
void vbl_cie1931_cmf(double nm, double xyz[3]);

/* CIE XYZ of a blackbody at `kelvin` (0 or less: black), normalised as `norm` says. */
void vbl_blackbody_xyz(double kelvin, vbl_blackbody_normalization norm, double xyz[3]);

/* Linear Rec.709 / sRGB primaries, D65 white, from CIE XYZ. */
vbl_vec3 vbl_xyz_to_rec709(const double xyz[3]);

/* RGB of a blackbody, negative (out of gamut) channels clamped to 0. */
vbl_vec3 vbl_blackbody_rgb(double kelvin, vbl_blackbody_normalization norm);

/* A per-scene table of vbl_blackbody_rgb at 1 K steps on [0, VBL_BLACKBODY_TABLE_MAX_K] with
 * linear interpolation; hotter temperatures are computed per lookup. */
#define VBL_BLACKBODY_TABLE_MAX_K 16384
typedef struct vbl_blackbody_table {
    vbl_blackbody_normalization norm;
    float* rgb; /* 3 * (VBL_BLACKBODY_TABLE_MAX_K + 1) */
} vbl_blackbody_table;

/* Fills the table (returns 0 on out of memory); free releases it (NULL rgb is ignored). */
int vbl_blackbody_table_build(vbl_blackbody_table* table, vbl_blackbody_normalization norm);
void vbl_blackbody_table_free(vbl_blackbody_table* table);
vbl_vec3 vbl_blackbody_table_rgb(const vbl_blackbody_table* table, double kelvin);

#endif
