/* Pixel positions drawn towards a point light's image (option pixel_focus).
 *
 * Single scattering along a camera ray that passes a point or spot light at distance h in a
 * medium is (Kulla and Fajardo 2012, sec. 4.1, the equiangular integral)
 *   int sigma_s p I / (h^2 + t^2) T dt ~ sigma_s p I (theta_b - theta_a) / h,
 * and near the light's image h is proportional to the raster distance r from the image. Over the
 * pixel that holds the image, int (1/r)^2 dA = int dr / r diverges: uniform pixel positions give
 * that pixel infinite variance (58 % of volume_direct's error in race_room, one pixel).
 *
 * In that pixel the driver draws the position from the mixture
 *   p(x) = alpha + (1 - alpha) / (r(x) I),   I = int_pixel dA / r   (the pixel has area 1),
 * and weights the sample 1 / p(x) (at most 1 / alpha): the 1/r part cancels the singularity, the
 * uniform part keeps every other layer's weight bounded. The 1/r density on the pixel square is
 * sampled exactly: the square splits into the four triangles from the image c to its edges; a
 * triangle with foot distance d and edge offsets e0 < e1 has integral
 * d (asinh(e1 / d) - asinh(e0 / d)); the edge point's offset is d sinh(uniform in asinh) and the
 * position uniform on the segment from c to it. Lights count when they are in front of the camera
 * and inside the box of the media; a pixel holds at most one focus (the first light's). */
#ifndef VBL_RENDER_PIXEL_FOCUS_H
#define VBL_RENDER_PIXEL_FOCUS_H

#include "scene/scene.h"

#define VBL_PIXEL_FOCUS_MAX 16
#define VBL_PIXEL_FOCUS_ALPHA 0.5

typedef struct vbl_pixel_focus {
    int px, py;      /* the pixel */
    double cx, cy;   /* the light's image, inside the pixel */
    double tri[4];   /* the four triangles' integrals of 1/r */
    double total;    /* I */
} vbl_pixel_focus;

typedef struct vbl_pixel_foci {
    int count;
    vbl_pixel_focus focus[VBL_PIXEL_FOCUS_MAX];
} vbl_pixel_foci;

/* The foci of `scene`'s point and spot lights inside the box [lo, hi] (has_box 0: none). */
void vbl_pixel_foci_build(const vbl_scene* scene, int has_box, vbl_vec3 lo, vbl_vec3 hi, vbl_pixel_foci* out);

/* The focus in pixel (px, py), or NULL. */
const vbl_pixel_focus* vbl_pixel_foci_find(const vbl_pixel_foci* foci, int px, int py);

/* A focus at image (cx, cy) inside pixel (px, py) (tests; vbl_pixel_foci_build uses it). */
int vbl_pixel_focus_make(int px, int py, double cx, double cy, vbl_pixel_focus* f);

/* Draws a raster position in f's pixel from the mixture (`choice` picks the part, (u, v) place
 * the point; all uniform in [0, 1)) and returns its weight 1 / p(x), in (0, 1 / alpha]. */
double vbl_pixel_focus_sample(const vbl_pixel_focus* f, double choice, double u, double v, double* sx, double* sy);

/* The mixture's density p at raster position (sx, sy) in f's pixel. */
double vbl_pixel_focus_pdf(const vbl_pixel_focus* f, double sx, double sy);

#endif
