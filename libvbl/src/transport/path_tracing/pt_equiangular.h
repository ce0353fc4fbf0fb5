/* pt's equiangular next-event estimation for point and spot lights (Kulla and Fajardo 2012,
 * "Importance Sampling Techniques for Path Tracing in Participating Media", sec. 4.1 equiangular
 * sampling, sec. 4.2 MIS with distance sampling), combined with the free-flight collision's NEE by
 * two-sample MIS (Veach 1997, eq. 9.13 / 9.14).
 *
 * For every segment of a path (origin, unit direction, up to the surface it hits) the single-
 * scattering integral towards light i
 *   I_i = int_t0^t1 T(t0, t) K(t, w_i) L_i(t) T_l(t) dt     (K = sum sigma_s p, the kernel)
 * is estimated twice: by the free-flight (delta-tracking) collision at density sigma_t(t) T(t0, t)
 * with the light picked uniformly among all N lights (pt's ordinary NEE), and by a distance t drawn
 * equiangularly towards a point/spot light picked uniformly among the N_eq such lights, with T(t0, t)
 * estimated by the render's transmittance estimator (ratio tracking: the product of (1 - sigma_t /
 * majorant) over tentative collisions, Novak et al. 2014, eq. 6) and sigma_t(t) looked up, so the
 * heterogeneous medium enters through the real/majorant density ratios, unbiased. On the camera
 * segment (pt.equiangular_camera_samples) pt draws n distances, one per stratum of the
 * equiangular CDF, each weighted 1/n, and T(t0, t) is the camera walk's running product where
 * the segment is thin (VBL_PT_EQ_WALK_DEPTH): no march there. The MIS weights
 * use q_ff(i, t) = sigma_t(t) exp(-tau_c(t0, t)) / N with tau_c the majorant segments' mid-bound
 * optical depth (volume/control_depth.h; exact in homogeneous media) and q_ea(i, t) = p_ea,i(t) /
 * N_eq: both are deterministic functions of (segment, i, t) and w_ff + w_ea = 1 wherever either
 * strategy can sample, so the sum stays unbiased whatever the approximation in q_ff costs in
 * variance.
 *
 * Quad lights (option pt.equiangular_quads): a point y is drawn uniformly on the quad first (the
 * NEE's own area sampling), then t equiangularly towards y. That path (x_t, y) can also come from
 * the collision's NEE and from the scattered ray hitting the quad (phase sampling), so the three
 * are weighted together (Veach 1997, eq. 9.13 / 9.14 over three strategies), each density per unit
 * t and solid angle at x: nee = q_ff(t) / N * p_l, phase = q_ff(t) * p_phase(wi), eq = p_ea(t | y)
 * / N_eq * p_l, with p_l the quad's area pdf in solid angle and q_ff(t) = sigma_t exp(-tau_c).
 * The medium is read through the medium interface (media/medium.h).
 *
 * On the camera segment pt may draw several collisions from one walk (pt.split_paths, n of them,
 * each with 1/n of the weight). The weights still use one collision's density, not n times it
 * (Veach's n_i p_i): n x moved the weight onto the collision strategy, whose samples spike near a
 * point light, and volume_direct in race_room was worse on each of 4 seeds (session 11). */
#ifndef VBL_TRANSPORT_PT_EQUIANGULAR_H
#define VBL_TRANSPORT_PT_EQUIANGULAR_H

#include "transport/common/emission_estimate.h"
#include "transport/common/estimator.h"
#include "transport/path_tracing/pt_camera_split.h"

/* 1 if options select equiangular NEE and the scene has a point or spot light (or a quad light
 * with pt.equiangular_quads) and media. */
int vbl_pt_equiangular_active(const vbl_render_context* ctx);
/* 1 if quad lights take part (equiangular active and pt.equiangular_quads). */
int vbl_pt_equiangular_quads_active(const vbl_render_context* ctx);

/* A medium vertex: at distance t (sigma_t there) on the segment (origin, unit direction, up to
 * t_surface) its free flight came from. */
typedef struct vbl_pt_eq_vertex {
    vbl_vec3 origin, direction;
    double t_surface, t, sigma_t;
} vbl_pt_eq_vertex;

enum { VBL_PT_EQ_NEE = 0, VBL_PT_EQ_PHASE = 1 };

/* With quad lights active: the MIS weight of the path from medium vertex v along unit wi to the
 * quad point at `distance`, for the collision's NEE (strategy VBL_PT_EQ_NEE) or the scattered
 * ray hitting the quad (VBL_PT_EQ_PHASE; phase_pdf the phase pdf of wi at v in both cases). */
double vbl_pt_equiangular_quad_weight(const vbl_render_context* ctx, const vbl_light* light,
                                      const vbl_pt_eq_vertex* v, vbl_vec3 wi, double distance, double phase_pdf,
                                      int strategy);

/* The camera walk's running product stands for T(t0, t) where the majorant segments' control
 * optical depth tau_c(t0, t) is below this, a march estimates it elsewhere. The walk (ratio
 * tracking at 8x the majorant, roulette below T^ = 0.1) has relative variance ~ exp(tau / 8) - 1
 * until its roulette, ~ 0.1 / T past it: in thin smoke it is as good as the march and costs
 * nothing, deep in a dense medium it is several times worse (bench/pt_ab, session 16:
 * race_dense_point volume_direct 0.58 with the walk everywhere against 0.18 with the march; 0.18 at
 * 1.5; race_room and smoky_lambert_room_thin keep the walk's gain). The choice depends only on
 * (segment, t), so each estimate stays unbiased. */
#define VBL_PT_EQ_WALK_DEPTH 1.5

/* The equiangular sample of one segment: adds w_ea K L T T_l / (p_ea / N_eq) * beta into *L.
 * t_surface: where the segment ends (INFINITY: escapes). u_pick picks the light, u_t the distance
 * (the caller draws both, whatever follows, so later dimensions keep their place); the
 * transmittance estimates draw from rng. phase_traced = 0 where the sampled vertex is the path's
 * last (max_bounces): no phase direction is traced from it, so a quad's MIS has two strategies.
 * samples (>= 1): that many samples, one per stratum (r + u_t) / samples of the equiangular CDF with
 * the light pick rotated by r / samples, each weighted 1 / samples (the media interval and the
 * light count computed once for them; pt.equiangular_camera_samples on the camera segment).
 * walk: the camera split's walk along this segment (the camera segment; else NULL): T(t0, t) is
 * its running product where tau_c(t0, t) < VBL_PT_EQ_WALK_DEPTH (times a march of the rest past
 * a capped walk), else the march's. */
void vbl_pt_equiangular_nee(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                            vbl_vec3 direction, double t_surface, vbl_vec3 beta, double u_pick, double u_t,
                            int samples, int phase_traced, vbl_medium_pdf_fn dir_pdf, const void* dir_pdf_data,
                            const vbl_pt_split_walk* walk, vbl_rng* rng, vbl_vec3* L);

/* MIS weight of the free-flight collision NEE at distance t (sigma_t there) on the segment
 * (origin, direction, t_surface) when it picked `light`: 1 unless the light is a point/spot light
 * and equiangular NEE is active (quads: vbl_pt_equiangular_quad_weight). */
double vbl_pt_equiangular_ff_weight(const vbl_render_context* ctx, const vbl_light* light, vbl_vec3 origin,
                                    vbl_vec3 direction, double t_surface, double t, double sigma_t);

#endif
