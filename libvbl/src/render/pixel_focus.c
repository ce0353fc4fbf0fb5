/* Pixel positions towards a point light's image (pixel_focus.h). */
#include "render/pixel_focus.h"

#include <math.h>
#include <string.h>

#include "scene/lights.h"

/* Triangle k of the pixel square [x0, x0+1] x [y0, y0+1] seen from c: its edge as a foot point,
 * a unit direction along the edge, the perpendicular distance d and the offsets e0 < e1 of the
 * edge's ends from the foot. Edges: 0 y = y0, 1 x = x0 + 1, 2 y = y0 + 1, 3 x = x0. */
static void vbl_focus_edge(const vbl_pixel_focus* f, int k, double* fx, double* fy, double* ax, double* ay, double* d,
                           double* e0, double* e1)
{
    const double x0 = f->px, y0 = f->py, x1 = x0 + 1.0, y1 = y0 + 1.0;
    switch (k) {
    case 0: *fx = f->cx, *fy = y0, *ax = 1.0, *ay = 0.0, *d = f->cy - y0, *e0 = x0 - f->cx, *e1 = x1 - f->cx; break;
    case 1: *fx = x1, *fy = f->cy, *ax = 0.0, *ay = 1.0, *d = x1 - f->cx, *e0 = y0 - f->cy, *e1 = y1 - f->cy; break;
    case 2: *fx = f->cx, *fy = y1, *ax = 1.0, *ay = 0.0, *d = y1 - f->cy, *e0 = x0 - f->cx, *e1 = x1 - f->cx; break;
    default: *fx = x0, *fy = f->cy, *ax = 0.0, *ay = 1.0, *d = f->cx - x0, *e0 = y0 - f->cy, *e1 = y1 - f->cy; break;
    }
}

int vbl_pixel_focus_make(int px, int py, double cx, double cy, vbl_pixel_focus* f)
{
    memset(f, 0, sizeof *f);
    if (!isfinite(cx) || !isfinite(cy)) return 0; /* fmax below would drop a NaN */
    /* the image within the pixel or VBL_PIXEL_FOCUS_REACH of its square */
    const double gx = fmax(0.0, fmax(px - cx, cx - (px + 1.0))), gy = fmax(0.0, fmax(py - cy, cy - (py + 1.0)));
    if (!(hypot(gx, gy) <= VBL_PIXEL_FOCUS_REACH)) return 0;
    f->px = px, f->py = py, f->cx = cx, f->cy = cy;
    double far = 0.0;
    for (int k = 0; k < 4; ++k) {
        double fx, fy, ax, ay, d, e0, e1;
        vbl_focus_edge(f, k, &fx, &fy, &ax, &ay, &d, &e0, &e1);
        /* int over the triangle (c, edge) of 1/r = int |d| / cos(theta) dtheta (r to the edge:
         * |d| / cos); an edge whose line c lies beyond (d < 0) is a near edge: its triangle lies
         * between c and the square and is subtracted (the square = the far triangles minus the
         * near ones, as signed areas seen from c) */
        const double a = fabs(d);
        const double m = a > 1e-12 ? a * (asinh(e1 / a) - asinh(e0 / a)) : 0.0;
        f->tri[k] = d > 0.0 ? m : 0.0;
        far += f->tri[k];
        f->total += d > 0.0 ? m : -m;
    }
    f->far_total = far;
    return f->total > 0.0 && isfinite(f->total) && far > 0.0 && isfinite(far);
}

void vbl_pixel_foci_build(const vbl_scene* scene, int has_box, vbl_vec3 lo, vbl_vec3 hi, vbl_pixel_foci* out)
{
    memset(out, 0, sizeof *out);
    if (!has_box) return;
    const vbl_camera* cam = &scene->camera;
    for (int i = 0; i < scene->light_count && out->count < VBL_PIXEL_FOCUS_MAX; ++i) {
        if (!vbl_light_local_in_box(&scene->lights[i], lo, hi)) continue;
        double sx, sy;
        if (!vbl_camera_raster(cam, scene->lights[i].position, &sx, &sy)) continue;
        if (!(sx >= 0.0 && sx < cam->width && sy >= 0.0 && sy < cam->height)) continue;
        /* the image's pixel and the pixels around it whose squares come within
         * VBL_PIXEL_FOCUS_REACH of the image (pixel_focus.h) */
        const int ix = (int)sx, iy = (int)sy;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int px = ix + dx, py = iy + dy;
                if (px < 0 || py < 0 || px >= cam->width || py >= cam->height) continue;
                if (out->count >= VBL_PIXEL_FOCUS_MAX || vbl_pixel_foci_find(out, px, py)) continue;
                if (vbl_pixel_focus_make(px, py, sx, sy, &out->focus[out->count])) ++out->count;
            }
    }
}

const vbl_pixel_focus* vbl_pixel_foci_find(const vbl_pixel_foci* foci, int px, int py)
{
    for (int i = 0; i < foci->count; ++i)
        if (foci->focus[i].px == px && foci->focus[i].py == py) return &foci->focus[i];
    return NULL;
}

double vbl_pixel_focus_pdf(const vbl_pixel_focus* f, double sx, double sy)
{
    const double r = hypot(sx - f->cx, sy - f->cy);
    const double focused = r > 0.0 ? 1.0 / (r * f->total) : INFINITY;
    return VBL_PIXEL_FOCUS_ALPHA + (1.0 - VBL_PIXEL_FOCUS_ALPHA) * focused;
}

/* One draw of the 1/r density over f's far triangles (u picks the triangle and the angle, v the
 * radius): a point of the pixel, or of the region between the image and the pixel (c outside). */
static void vbl_focus_far_point(const vbl_pixel_focus* f, double u, double v, double* sx, double* sy)
{
    double target = u * f->far_total, acc = 0.0;
    int k = 0;
    while (k < 3 && (f->tri[k] <= 0.0 || target >= acc + f->tri[k])) acc += f->tri[k++];
    while (k > 0 && !(f->tri[k] > 0.0)) --k; /* rounding past the last triangle with mass */
    double s = f->tri[k] > 0.0 ? (target - acc) / f->tri[k] : 0.5;
    s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
    double fx, fy, ax, ay, d, e0, e1;
    vbl_focus_edge(f, k, &fx, &fy, &ax, &ay, &d, &e0, &e1);
    const double a0 = asinh(e0 / d), a1 = asinh(e1 / d);
    const double e = d * sinh(a0 + s * (a1 - a0)); /* offset along the edge */
    const double ex = fx + ax * e, ey = fy + ay * e;
    /* uniform in r along the ray: the density 1/r is r dr dtheta / r */
    *sx = f->cx + v * (ex - f->cx);
    *sy = f->cy + v * (ey - f->cy);
}

double vbl_pixel_focus_sample(const vbl_pixel_focus* f, double choice, double u, double v, vbl_rng* rng, double* sx,
                              double* sy)
{
    const int inside = f->cx >= f->px && f->cx <= f->px + 1.0 && f->cy >= f->py && f->cy <= f->py + 1.0;
    int uniform = choice < VBL_PIXEL_FOCUS_ALPHA;
    if (!uniform && inside) {
        vbl_focus_far_point(f, u, v, sx, sy);
        /* keep the position inside the pixel against rounding */
        *sx = fmin(fmax(*sx, (double)f->px), nextafter(f->px + 1.0, f->px));
        *sy = fmin(fmax(*sy, (double)f->py), nextafter(f->py + 1.0, f->py));
    } else if (!uniform) {
        /* the image outside the pixel: rejection from the far triangles, keeping the points in
         * the pixel (accepted with probability total / far_total; the region between the image
         * and the near edges is what is rejected) */
        int tries = 0;
        for (;;) {
            vbl_focus_far_point(f, u, v, sx, sy);
            if (*sx >= f->px && *sx < f->px + 1.0 && *sy >= f->py && *sy < f->py + 1.0) break;
            if (++tries == VBL_PIXEL_FOCUS_TRIES || !rng) { /* pixel_focus.h: never in practice */
                uniform = 1;
                break;
            }
            u = vbl_rng_uniform(rng);
            v = vbl_rng_uniform(rng);
        }
    }
    if (uniform) {
        *sx = f->px + u;
        *sy = f->py + v;
    }
    const double p = vbl_pixel_focus_pdf(f, *sx, *sy);
    return p > 0.0 && isfinite(p) ? 1.0 / p : 0.0; /* the image itself (r = 0): weight 0, measure zero */
}
