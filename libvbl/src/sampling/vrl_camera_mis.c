/* Transmittance-aware camera-ray / VRL pair sampling by one-sample MIS (vrl_camera_mis.h). */
#include "sampling/vrl_camera_mis.h"

#include "sampling/equiangular.h"

double vbl_vrl_camera_technique_pdf(const vbl_vrl_pair* p, const vbl_step_pdf* camera, double u, double v)
{
    if (!p->valid) return 0.0;
    double pu = vbl_step_pdf_pdf(camera, u);
    if (!(pu > 0.0)) return 0.0;
    vbl_vec3 xu = vbl_v3_madd(p->c_o, p->c_d, u);
    return pu * vbl_equiangular_pdf(p->l_o, p->l_d, p->v0, p->v1, xu, v);
}

double vbl_vrl_camera_mis_density(const vbl_vrl_pair* p, const vbl_step_pdf* camera, double u, double v)
{
    const double c = VBL_VRL_CAMERA_MIS_SHARE;
    return c * vbl_vrl_pair_density(p, u, v) + (1.0 - c) * vbl_vrl_camera_technique_pdf(p, camera, u, v);
}

int vbl_vrl_camera_mis_draw(const vbl_vrl_pair* p, const vbl_step_pdf* camera, double xi_choice, double xi1,
                            double xi2, vbl_vrl_pair_sample* out)
{
    const double c = VBL_VRL_CAMERA_MIS_SHARE;
    out->pdf = 0.0;
    if (!p->valid) return 0;
    double p1, p2;
    if (xi_choice < c) {
        if (!vbl_vrl_pair_draw(p, xi1, xi2, out) || !(out->pdf > 0.0)) return 0;
        p1 = out->pdf;
        p2 = vbl_vrl_camera_technique_pdf(p, camera, out->u, out->v);
    } else {
        double pu;
        double u = vbl_step_pdf_sample(camera, xi1, &pu);
        if (!(pu > 0.0) || u < p->u0 || u > p->u1) return 0;
        vbl_vec3 xu = vbl_v3_madd(p->c_o, p->c_d, u);
        double pv;
        double v = vbl_equiangular_sample(p->l_o, p->l_d, p->v0, p->v1, xu, xi2, &pv);
        if (!(pv > 0.0)) return 0;
        out->u = u;
        out->v = v;
        /* the densities as vbl_vrl_camera_mis_density evaluates them at (u, v) */
        p2 = vbl_vrl_camera_technique_pdf(p, camera, u, v);
        p1 = vbl_vrl_pair_density(p, u, v);
    }
    out->pdf = c * p1 + (1.0 - c) * p2;
    return out->pdf > 0.0;
}
