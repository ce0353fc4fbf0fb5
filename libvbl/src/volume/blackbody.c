/* Blackbody colours (blackbody.h). Planck's law B(lambda, T) = 2 h c^2 / lambda^5 /
 * (exp(h c / (lambda k T)) - 1) is summed at the 10 nm samples of the CIE 1931 table
 * (360-830 nm) against the colour matching functions (CIE 15:2004, sec. 7.1). */
#include "volume/blackbody.h"

#include <math.h>
#include <stdlib.h>

#include "cie1931_table.h"

/* CIE 1931 2-degree observer, 10 nm table generated at configure time (gen_cie1931.py), linearly
 * interpolated; 0 outside 360-830 nm. */
void vbl_cie1931_cmf(double nm, double xyz[3])
{
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    double u = (nm - VBL_CIE1931_FIRST_NM) / VBL_CIE1931_STEP_NM;
    if (!(u >= 0.0 && u <= VBL_CIE1931_COUNT - 1)) return;
    int i = (int)u;
    if (i >= VBL_CIE1931_COUNT - 1) i = VBL_CIE1931_COUNT - 2;
    double f = u - i;
    for (int k = 0; k < 3; ++k)
        xyz[k] = vbl_cie1931_table[i][k] + f * (vbl_cie1931_table[i + 1][k] - vbl_cie1931_table[i][k]);
}

/* Planck's law in W / (m^2 sr m) at wavelength `m` metres. */
static double vbl_planck(double m, double kelvin)
{
    const double h = 6.62606957e-34, c = 299792458.0, kb = 1.3806488e-23;
    double l5 = m * m * m * m * m;
    return 2.0 * h * c * c / (l5 * expm1(h * c / (m * kb * kelvin)));
}

void vbl_blackbody_xyz(double kelvin, vbl_blackbody_normalization norm, double xyz[3])
{
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    if (!(kelvin > 0.0) || !isfinite(kelvin)) return;
    double y_integral = 0.0;
    for (int i = 0; i < VBL_CIE1931_COUNT; ++i) {
        const double* cmf = vbl_cie1931_table[i];
        double b = vbl_planck((VBL_CIE1931_FIRST_NM + VBL_CIE1931_STEP_NM * i) * 1e-9, kelvin);
        for (int k = 0; k < 3; ++k) xyz[k] += b * cmf[k];
        y_integral += cmf[1];
    }
    double scale;
    if (norm == VBL_BLACKBODY_LUMINANCE) {
        scale = xyz[1] > 0.0 ? 1.0 / xyz[1] : 0.0;
    } else {
        /* pbrt-v4's normalised blackbody (Pharr et al. 2023, sec. 4.4.1): divided by B at Wien's
         * displacement peak, and XYZ by the integral of ybar as pbrt's SpectrumToXYZ does */
        double peak = vbl_planck(2.8977721e-3 / kelvin, kelvin);
        scale = peak > 0.0 ? 1.0 / (peak * y_integral) : 0.0;
    }
    for (int k = 0; k < 3; ++k) xyz[k] = isfinite(xyz[k] * scale) ? xyz[k] * scale : 0.0;
}

vbl_vec3 vbl_xyz_to_rec709(const double xyz[3])
{
    /* IEC 61966-2-1 (sRGB) matrix, D65 */
    return vbl_v3(3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2],
                  -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2],
                  0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2]);
}

vbl_vec3 vbl_blackbody_rgb(double kelvin, vbl_blackbody_normalization norm)
{
    double xyz[3];
    vbl_blackbody_xyz(kelvin, norm, xyz);
    vbl_vec3 c = vbl_xyz_to_rec709(xyz);
    return vbl_v3(fmax(c.x, 0.0), fmax(c.y, 0.0), fmax(c.z, 0.0));
}

int vbl_blackbody_table_build(vbl_blackbody_table* table, vbl_blackbody_normalization norm)
{
    table->norm = norm;
    table->rgb = malloc(sizeof(float) * 3 * (VBL_BLACKBODY_TABLE_MAX_K + 1));
    if (!table->rgb) return 0;
    for (int k = 0; k <= VBL_BLACKBODY_TABLE_MAX_K; ++k) {
        vbl_vec3 c = vbl_blackbody_rgb((double)k, norm);
        table->rgb[3 * k] = (float)c.x;
        table->rgb[3 * k + 1] = (float)c.y;
        table->rgb[3 * k + 2] = (float)c.z;
    }
    return 1;
}

void vbl_blackbody_table_free(vbl_blackbody_table* table)
{
    free(table->rgb);
    table->rgb = NULL;
}

vbl_vec3 vbl_blackbody_table_rgb(const vbl_blackbody_table* table, double kelvin)
{
    if (!(kelvin > 0.0)) return vbl_v3(0.0, 0.0, 0.0);
    if (kelvin >= VBL_BLACKBODY_TABLE_MAX_K) return vbl_blackbody_rgb(kelvin, table->norm);
    int k = (int)kelvin;
    double f = kelvin - k;
    const float* a = table->rgb + 3 * k;
    return vbl_v3(a[0] + f * (a[3] - a[0]), a[1] + f * (a[4] - a[1]), a[2] + f * (a[5] - a[2]));
}
