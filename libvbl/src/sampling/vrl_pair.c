/* VRL / camera-ray product sampling: VRL paper section 4 (eqs 10-15) and appendix A (eqs 16-20). */
#include "sampling/vrl_pair.h"

#include <stddef.h>

#include "sampling/cauchy.h"
#include "sampling/equiangular.h"
#include "sampling/phase_hg.h"
#include "sampling/piecewise_linear.h"

/* Project the VRL onto the plane perpendicular to the camera ray (cross products keep the
 * perpendicular parts accurate for near-parallel lines):
 *   P0 = perpendicular offset of the VRL start, q = perpendicular part of l_d, |q| = sin theta.
 * The distance of l(v0 + t) to the camera line is |P0 + t q| = sqrt(h^2 + (beta + s t)^2),
 * h the closest-approach distance of the lines, beta = P0 . q / s (eq 10's vhat0 sin theta). */
void vbl_vrl_line_projection(vbl_vec3 c_o, vbl_vec3 c_d, vbl_vec3 l_o, vbl_vec3 l_d, double v0, double* beta,
                             double* s, double* h)
{
    vbl_vec3 r = vbl_v3_sub(vbl_v3_madd(l_o, l_d, v0), c_o);
    vbl_vec3 p0 = vbl_v3_cross(c_d, vbl_v3_cross(r, c_d));
    vbl_vec3 lxc = vbl_v3_cross(l_d, c_d);
    *s = vbl_v3_length(lxc);
    *beta = 0.0;
    *h = vbl_v3_length(p0);
    if (*s > 0.0) {
        vbl_vec3 qhat = vbl_v3_scale(vbl_v3_cross(c_d, lxc), 1.0 / *s);
        *beta = vbl_v3_dot(p0, qhat);
        *h = vbl_v3_length(vbl_v3_cross(p0, qhat));
    }
}

int vbl_vrl_pair_init(vbl_vrl_pair* p, const vbl_segment* camera, const vbl_segment* light, double g_camera,
                      double g_light)
{
    const vbl_vec3 c_o = camera->origin, c_d = camera->direction, l_o = light->origin, l_d = light->direction;
    const double u0 = camera->t0, u1 = camera->t1, v0 = light->t0, v1 = light->t1;
    p->c_o = c_o;
    p->c_d = c_d;
    p->l_o = l_o;
    p->l_d = l_d;
    p->u0 = u0;
    p->u1 = u1;
    p->v0 = v0;
    p->v1 = v1;
    p->g_camera = g_camera;
    p->g_light = g_light;
    p->isotropic = g_camera == 0.0 && g_light == 0.0;
    p->valid = 0;
    if (!(u1 > u0) || !(v1 > v0)) {
        vbl_sinh_marginal_init(&p->marginal, 0.0, 0.0, 0.0, 0.0);
        return 0;
    }
    double beta, s, h;
    vbl_vrl_line_projection(c_o, c_d, l_o, l_d, v0, &beta, &s, &h);
    p->valid = vbl_sinh_marginal_init(&p->marginal, beta, s, h, v1 - v0);
    return p->valid;
}

/* Stage-2 geometry about the VRL point x = l(v): projection parameter u_p of x onto the camera
 * line, perpendicular distance D (floored like the Cauchy sampler), unit normal n from x towards
 * the camera line, and the angular range [phi0, phi1] with u = u_p + D tan(phi). */
typedef struct arc {
    double up, d, phi0, phi1;
    vbl_vec3 n;
} arc;

static int arc_make(const vbl_vrl_pair* p, double v, arc* a)
{
    vbl_vec3 x = vbl_v3_madd(p->l_o, p->l_d, v);
    vbl_vec3 rel = vbl_v3_sub(x, p->c_o);
    a->up = vbl_v3_dot(rel, p->c_d);
    vbl_vec3 perp = vbl_v3_cross(p->c_d, vbl_v3_cross(rel, p->c_d)); /* rel minus its c_d part */
    double d = vbl_v3_length(perp);
    double lo = p->u0 - a->up, hi = p->u1 - a->up;
    a->d = fmax(d, VBL_SAMPLING_H_FLOOR_REL * fmax(fabs(lo), fabs(hi)));
    if (!(a->d > 0.0)) return 0;
    if (d > 0.0) {
        a->n = vbl_v3_scale(perp, -1.0 / d);
    } else {
        vbl_vec3 b;
        vbl_v3_basis(p->c_d, &a->n, &b); /* x on the camera line: any perpendicular */
    }
    a->phi0 = atan2(lo, a->d);
    a->phi1 = atan2(hi, a->d);
    return a->phi1 > a->phi0;
}

/* f_uv(phi): product of the two HG lobes along the arc; omega = cos(phi) n + sin(phi) c_d is the
 * direction from the VRL point to the camera point u = u_p + D tan(phi). */
static double arc_fuv(const vbl_vrl_pair* p, const arc* a, double phi)
{
    double c = cos(phi), s = sin(phi);
    vbl_vec3 omega = vbl_v3_add(vbl_v3_scale(a->n, c), vbl_v3_scale(p->c_d, s));
    return vbl_hg_eval(p->g_light, vbl_v3_dot(p->l_d, omega)) * vbl_hg_eval(p->g_camera, -s);
}

/* Appendix A: M vertices on [phi0, phi1], cosine-warped (eq 19), with one vertex moved onto the
 * extremum of the VRL lobe when it lies on the arc (eqs 16-18 and 20) and the others
 * cosine-warped within each side. */
static void arc_vertices(const vbl_vrl_pair* p, const arc* a, double* phi)
{
    const int m = VBL_VRL_PAIR_VERTICES;
    double lo = a->phi0, hi = a->phi1, span = hi - lo;
    /* Eqs 16-18: the projection e of l_d onto the plane of the arc, as an angle in that plane;
     * the opposite direction (the lobe's minimum, or its peak when g < 0) is e + pi. */
    double ex = vbl_v3_dot(p->l_d, a->n), ey = vbl_v3_dot(p->l_d, p->c_d);
    double peak = 0.0;
    int has_peak = 0;
    if (ex != 0.0 || ey != 0.0) {
        double cand[2] = {atan2(ey, ex), atan2(-ey, -ex)};
        double margin = 1e-6 * span;
        for (int k = 0; k < 2 && !has_peak; ++k) {
            if (cand[k] > lo + margin && cand[k] < hi - margin) {
                peak = cand[k];
                has_peak = 1;
            }
        }
    }
    if (!has_peak) {
        for (int j = 0; j < m; ++j) phi[j] = lo + 0.5 * span * (1.0 - cos(VBL_PI * j / (m - 1))); /* eq 19 */
    } else {
        int jp = (int)floor((peak - lo) / span * (m - 1) + 0.5); /* eq 20 */
        jp = jp < 1 ? 1 : (jp > m - 2 ? m - 2 : jp);
        for (int j = 0; j <= jp; ++j) phi[j] = lo + 0.5 * (peak - lo) * (1.0 - cos(VBL_PI * j / jp));
        for (int j = jp; j < m; ++j)
            phi[j] = peak + 0.5 * (hi - peak) * (1.0 - cos(VBL_PI * (j - jp) / (m - 1 - jp)));
        phi[jp] = peak;
    }
    phi[0] = lo;
    phi[m - 1] = hi;
    for (int j = 1; j < m; ++j) phi[j] = vbl_clamp(phi[j], phi[j - 1], hi); /* non-decreasing */
}

static int arc_pwl(const vbl_vrl_pair* p, const arc* a, vbl_pwl* pwl)
{
    double phi[VBL_VRL_PAIR_VERTICES], f[VBL_VRL_PAIR_VERTICES];
    arc_vertices(p, a, phi);
    for (int j = 0; j < VBL_VRL_PAIR_VERTICES; ++j) f[j] = arc_fuv(p, a, phi[j]);
    return vbl_pwl_init(pwl, phi, f, VBL_VRL_PAIR_VERTICES);
}

double vbl_vrl_pair_marginal_pdf(const vbl_vrl_pair* p, double v)
{
    if (!p->valid || v < p->v0 || v > p->v1) return 0.0;
    return vbl_sinh_marginal_pdf_t(&p->marginal, v - p->v0);
}

double vbl_vrl_pair_conditional_pdf(const vbl_vrl_pair* p, double v, double u)
{
    if (!p->valid || u < p->u0 || u > p->u1) return 0.0;
    vbl_vec3 x = vbl_v3_madd(p->l_o, p->l_d, v);
    if (p->isotropic) return vbl_equiangular_pdf(p->c_o, p->c_d, p->u0, p->u1, x, u); /* eq 14 */
    arc a;
    vbl_pwl pwl;
    if (!arc_make(p, v, &a) || !arc_pwl(p, &a, &pwl)) return 0.0;
    double du = u - a.up;
    double phi = atan2(du, a.d);
    return vbl_pwl_pdf(&pwl, vbl_clamp(phi, a.phi0, a.phi1)) * a.d / (a.d * a.d + du * du);
}

double vbl_vrl_pair_draw_conditional(const vbl_vrl_pair* p, double v, double xi, double* pdf)
{
    double u = p->u0, pu = 0.0;
    if (p->isotropic) {
        vbl_vec3 x = vbl_v3_madd(p->l_o, p->l_d, v);
        u = vbl_equiangular_sample(p->c_o, p->c_d, p->u0, p->u1, x, xi, &pu); /* eq 14 */
    } else {
        arc a;
        vbl_pwl pwl;
        if (arc_make(p, v, &a) && arc_pwl(p, &a, &pwl)) {
            double phi = vbl_pwl_sample(&pwl, xi, NULL);
            u = vbl_clamp(a.up + a.d * tan(phi), p->u0, p->u1);
            double du = u - a.up;
            double phi_u = vbl_clamp(atan2(du, a.d), a.phi0, a.phi1);
            pu = vbl_pwl_pdf(&pwl, phi_u) * a.d / (a.d * a.d + du * du); /* Jacobian dphi/du = D / dist^2 */
        }
    }
    *pdf = pu;
    return u;
}

int vbl_vrl_pair_draw(const vbl_vrl_pair* p, double xi1, double xi2, vbl_vrl_pair_sample* out)
{
    out->u = p->u0;
    out->v = p->v0;
    out->pdf = 0.0;
    if (!p->valid) return 0;
    double t = vbl_sinh_marginal_sample_t(&p->marginal, xi1, NULL); /* eq 13 */
    double v = vbl_clamp(p->v0 + t, p->v0, p->v1);
    /* Densities are evaluated at the returned (u, v) exactly as vbl_vrl_pair_density does. */
    double pv = vbl_vrl_pair_marginal_pdf(p, v);
    if (!(pv > 0.0)) return 0;
    double pu;
    double u = vbl_vrl_pair_draw_conditional(p, v, xi2, &pu);
    if (!(pu > 0.0)) return 0;
    out->u = u;
    out->v = v;
    out->pdf = pv * pu;
    return 1;
}

void vbl_vrl_pair_swap(const vbl_vrl_pair* p, vbl_vrl_pair* out)
{
    *out = *p;
    out->c_o = p->l_o;
    out->c_d = p->l_d;
    out->l_o = p->c_o;
    out->l_d = p->c_d;
    out->u0 = p->v0;
    out->u1 = p->v1;
    out->v0 = p->u0;
    out->v1 = p->u1;
    out->g_camera = p->g_light;
    out->g_light = p->g_camera;
    vbl_sinh_marginal_init(&out->marginal, 0.0, 0.0, 0.0, 0.0); /* no marginal: conditionals only */
}

double vbl_vrl_pair_density(const vbl_vrl_pair* p, double u, double v)
{
    double pv = vbl_vrl_pair_marginal_pdf(p, v);
    return pv > 0.0 ? pv * vbl_vrl_pair_conditional_pdf(p, v, u) : 0.0;
}

int vbl_vrl_pair_sample_draw(const vbl_segment* camera, const vbl_segment* light, double g_camera, double g_light,
                             double xi1, double xi2, vbl_vrl_pair_sample* out)
{
    vbl_vrl_pair p;
    vbl_vrl_pair_init(&p, camera, light, g_camera, g_light);
    return vbl_vrl_pair_draw(&p, xi1, xi2, out);
}

double vbl_vrl_pair_pdf(const vbl_segment* camera, const vbl_segment* light, double g_camera, double g_light,
                        double u, double v)
{
    vbl_vrl_pair p;
    vbl_vrl_pair_init(&p, camera, light, g_camera, g_light);
    return vbl_vrl_pair_density(&p, u, v);
}

double vbl_vrl_pair_phase_geometry(const vbl_vrl_pair* p, double u, double v)
{
    vbl_vec3 xc = vbl_v3_madd(p->c_o, p->c_d, u);
    vbl_vec3 xl = vbl_v3_madd(p->l_o, p->l_d, v);
    vbl_vec3 dvec = vbl_v3_sub(xc, xl);
    double w2 = vbl_v3_dot(dvec, dvec);
    if (!(w2 > 0.0)) return 0.0;
    vbl_vec3 omega = vbl_v3_scale(dvec, 1.0 / sqrt(w2));
    return vbl_hg_eval(p->g_light, vbl_v3_dot(p->l_d, omega)) *
           vbl_hg_eval(p->g_camera, -vbl_v3_dot(p->c_d, omega)) / w2;
}
