/* Material dispatch. Lambert is implemented here; Phong and GGX lobes are in material_phong.c
 * and material_ggx.c (to come). */
#include "material/material.h"

#include "sampling/sphere.h"


static vbl_vec3 vbl_lambert_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    if (vbl_v3_dot(n, wo) <= 0.0 || vbl_v3_dot(n, wi) <= 0.0) return vbl_v3(0.0, 0.0, 0.0);
    return vbl_v3_scale(m->albedo, VBL_INV_PI);
}

static double vbl_cosine_pdf(vbl_vec3 n, vbl_vec3 wi)
{
    double c = vbl_v3_dot(n, wi);
    return c > 0.0 ? c * VBL_INV_PI : 0.0;
}

/* Cosine-weighted hemisphere about n (Malley): pdf cos / pi. */
static int vbl_cosine_sample(vbl_vec3 n, double u1, double u2, vbl_vec3* wi, double* pdf)
{
    double r = sqrt(u1), phi = 2.0 * VBL_PI * u2;
    double x = r * cos(phi), y = r * sin(phi), z = sqrt(fmax(0.0, 1.0 - u1));
    vbl_vec3 t, b;
    vbl_v3_basis(n, &t, &b);
    *wi = vbl_v3_normalize(vbl_v3_add(vbl_v3_add(vbl_v3_scale(t, x), vbl_v3_scale(b, y)), vbl_v3_scale(n, z)));
    *pdf = vbl_cosine_pdf(n, *wi);
    return *pdf > 0.0;
}

vbl_vec3 vbl_material_eval(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    return vbl_lambert_eval(m, n, wo, wi);
}

double vbl_material_pdf(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, vbl_vec3 wi)
{
    (void)m;
    if (vbl_v3_dot(n, wo) <= 0.0) return 0.0;
    return vbl_cosine_pdf(n, wi);
}

int vbl_material_sample(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo, double u0, double u1, double u2,
                        vbl_vec3* wi, double* pdf, vbl_vec3* f)
{
    (void)u0;
    if (vbl_v3_dot(n, wo) <= 0.0 || !vbl_cosine_sample(n, u1, u2, wi, pdf)) return 0;
    *f = vbl_lambert_eval(m, n, wo, *wi);
    return 1;
}

vbl_vec3 vbl_material_max_direction(const vbl_material* m, vbl_vec3 n, vbl_vec3 wo)
{
    (void)m;
    (void)wo;
    return n;
}

int vbl_material_is_diffuse(const vbl_material* m) { return m->type == VBL_MATERIAL_LAMBERT; }

double vbl_material_max_albedo(const vbl_material* m)
{
    return vbl_v3_max_component(vbl_v3_add(m->albedo, m->type == VBL_MATERIAL_LAMBERT ? vbl_v3(0, 0, 0) : m->specular));
}
