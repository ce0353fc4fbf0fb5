/* VRL paper eqs (9)-(13): the marginal density of a position on a VRL segment proportional to
 * the inverse distance to an infinite line (the camera ray), i.e. eq (10)
 *     pdf(vhat) ~ pi / sqrt(h^2 + vhat^2 sin^2 theta),
 * normalised by eq (11), with CDF eq (12) and inverse CDF eq (13)
 *     vhat = h sinh(lerp(A(vhat0), A(vhat1), xi)) / sin theta,   A(x) = asinh(x sin theta / h).
 *
 * Implementation form (numerically stable, no division by sin theta or h):
 * a point at parameter t in [0, len] along the segment is at distance
 *     dist(t) = sqrt(h^2 + (beta + s t)^2)
 * from the line, where s = sin theta >= 0, h is the closest-approach distance of the two lines
 * and beta = vhat0 sin theta is the signed offset of the segment start along the projected VRL
 * direction. The sampler inverts the CDF with the sinh addition theorem, so s -> 0 (parallel
 * lines) continuously becomes the uniform density (the analytic limit) without a special case,
 * and h = 0 exactly (crossing lines) is raised to VBL_SAMPLING_H_FLOOR_REL times the segment
 * scale (len + distance of the segment start). The pdf returned is always the density sampled. */
#ifndef VBL_SAMPLING_SINH_MARGINAL_H
#define VBL_SAMPLING_SINH_MARGINAL_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vbl_sinh_marginal {
    double beta, s, h, len; /* geometry (h floored) */
    double dist0;           /* sqrt(h^2 + beta^2): distance of the segment start to the line */
    double norm;            /* G = integral_0^len dt / dist(t) (eq 11 divided by pi) */
    double width;           /* s G = A(vhat1) - A(vhat0) */
    int valid;              /* 0: no support (zero length or no scale) */
} vbl_sinh_marginal;

/* Sets up the marginal for t in [0, len]; returns m->valid. */
int vbl_sinh_marginal_init(vbl_sinh_marginal* m, double beta, double sin_theta, double h, double len);
/* Samples t in [0, len]; *pdf per unit t (may be NULL, 0 when invalid). */
double vbl_sinh_marginal_sample_t(const vbl_sinh_marginal* m, double xi, double* pdf);
double vbl_sinh_marginal_pdf_t(const vbl_sinh_marginal* m, double t);

/* Paper form: vhat in [vhat0, vhat1] measured from the closest point of the VRL line, eq (13)
 * and eq (9)/(10)/(11). sin_theta in [0, 1], h >= 0. Zero length: returns vhat0, *pdf = 0. */
double vbl_sinh_marginal_sample(double h, double sin_theta, double vhat0, double vhat1, double xi, double* pdf);
double vbl_sinh_marginal_pdf(double h, double sin_theta, double vhat0, double vhat1, double vhat);

#ifdef __cplusplus
}
#endif

#endif
