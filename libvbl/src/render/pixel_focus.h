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
 * and inside the box of the media; a pixel holds at most one focus (the first light's).
 *
 * The pixels around the image's pixel have the same 1/r integrand at their squares' near side:
 * an image 0.05 px past a pixel's edge gives that pixel int (1/r)^2 dA ~ log(1 / 0.05), large
 * though finite (in race_room the lamp's neighbour held 30.9 of the lamp pixel's 42.7 standard
 * deviation of volume_direct). Every pixel of the 3 x 3 block around the image whose square comes
 * within VBL_PIXEL_FOCUS_REACH of it draws from the same mixture. With c outside the square the
 * four edges split into far ones (c on their inner side, d > 0) and near ones: the square is the
 * far triangles minus the near ones as signed areas seen from c, so I = sum over far edges minus
 * sum over near edges of the formula above. Points are drawn from the far triangles' 1/r density
 * (uniform in r along a ray from c) and kept when they fall in the pixel: an exact rejection
 * sampler, accepting with probability I / (sum over far edges). */
#ifndef VBL_RENDER_PIXEL_FOCUS_H
#define VBL_RENDER_PIXEL_FOCUS_H

#include "scene/scene.h"

#include "core/rng.h"

/* Foci per render: 9 pixels around each of up to 16 lights' images. */
#define VBL_PIXEL_FOCUS_MAX 144
#define VBL_PIXEL_FOCUS_ALPHA 0.5
/* How far (raster units) a pixel's square may lie from the image and still draw towards it. */
#define VBL_PIXEL_FOCUS_REACH 1.0
/* Rejection draws per sample for an image outside the pixel. Within the reach the acceptance is
 * at least 0.36 (an image 1 pixel from a corner, diagonally): a sample that takes them all (and
 * falls back to a uniform position) has probability below 1e-50. */
#define VBL_PIXEL_FOCUS_TRIES 256

typedef struct vbl_pixel_focus {
    int px, py;      /* the pixel */
    double cx, cy;   /* the light's image, inside the pixel or within VBL_PIXEL_FOCUS_REACH of it */
    double tri[4];   /* the far triangles' integrals of 1/r (0 for a near edge) */
    double far_total; /* their sum (= total when the image is inside the pixel) */
    double total;    /* I, the integral of 1/r over the pixel */
} vbl_pixel_focus;

typedef struct vbl_pixel_foci {
    int count;
    vbl_pixel_focus focus[VBL_PIXEL_FOCUS_MAX];
} vbl_pixel_foci;

/* The foci of `scene`'s point and spot lights inside the box [lo, hi] (has_box 0: none). */
void vbl_pixel_foci_build(const vbl_scene* scene, int has_box, vbl_vec3 lo, vbl_vec3 hi, vbl_pixel_foci* out);

/* The focus in pixel (px, py), or NULL. */
const vbl_pixel_focus* vbl_pixel_foci_find(const vbl_pixel_foci* foci, int px, int py);

/* A focus at image (cx, cy) for pixel (px, py): 0 (no focus) if the image is farther than
 * VBL_PIXEL_FOCUS_REACH from the pixel's square (tests; vbl_pixel_foci_build uses it). */
int vbl_pixel_focus_make(int px, int py, double cx, double cy, vbl_pixel_focus* f);

/* Draws a raster position in f's pixel from the mixture (`choice` picks the part, (u, v) place
 * the point; all uniform in [0, 1); an image outside the pixel draws its rejected tries' numbers
 * from rng) and returns its weight 1 / p(x), in (0, 1 / alpha]. */
double vbl_pixel_focus_sample(const vbl_pixel_focus* f, double choice, double u, double v, vbl_rng* rng, double* sx,
                              double* sy);

/* The mixture's density p at raster position (sx, sy) in f's pixel. */
double vbl_pixel_focus_pdf(const vbl_pixel_focus* f, double sx, double sy);

#endif
