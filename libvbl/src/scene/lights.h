/* Light sampling and evaluation for next-event estimation and MIS. Directions are unit vectors
 * from the shading point toward the light; pdfs are per unit solid angle (delta lights: 1). */
#ifndef VBL_SCENE_LIGHTS_H
#define VBL_SCENE_LIGHTS_H

#include "scene/scene.h"

typedef struct vbl_light_sample {
    vbl_vec3 wi;       /* unit, from the point toward the light */
    double distance;   /* to the sampled light point; INFINITY for distant/environment */
    vbl_vec3 li;       /* incident radiance (area/env) or intensity/r^2 / irradiance (delta) */
    double pdf;        /* solid-angle pdf of wi (1 for delta lights) */
    int is_delta;
} vbl_light_sample;

static inline int vbl_light_is_delta(const vbl_light* light)
{
    return light->type == VBL_LIGHT_POINT || light->type == VBL_LIGHT_SPOT || light->type == VBL_LIGHT_DISTANT;
}

/* 1 for a point or spot light whose position lies in the box [lo, hi] (a light inside the media:
 * pixel_focus, pt.light_focus), where single scattering near it grows like 1/distance. */
static inline int vbl_light_local_in_box(const vbl_light* light, vbl_vec3 lo, vbl_vec3 hi)
{
    if (light->type != VBL_LIGHT_POINT && light->type != VBL_LIGHT_SPOT) return 0;
    const vbl_vec3 p = light->position;
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
}

/* Spot falloff: 1 inside the inner cone, 0 outside the outer cone, smoothstep in cos between
 * (s = (cos - cos_outer) / (cos_inner - cos_outer), falloff = s^2 (3 - 2 s)). */
double vbl_spot_falloff(const vbl_light* light, double cos_axis);

/* Samples incident light at `point` with (u1, u2) in [0,1)^2. Returns 0 when the sample carries
 * no light (behind a one-sided quad, outside a spot cone, at the light's position). */
int vbl_light_sample_incident(const vbl_light* light, vbl_vec3 point, double u1, double u2,
                              vbl_light_sample* out);

/* Solid-angle pdf with which vbl_light_sample_incident would produce `wi` at `point` (0 for
 * delta lights and directions that miss the light). */
double vbl_light_pdf(const vbl_light* light, vbl_vec3 point, vbl_vec3 wi);

/* Ray (origin, unit direction) against a quad light's emitting side: returns 1 and the hit
 * distance when the ray hits the front face (dot(direction, normal) < 0). */
int vbl_quad_intersect(const vbl_light* light, vbl_vec3 origin, vbl_vec3 direction, double* t_hit);

/* MIS weight for a strategy with pdf `a` against one with pdf `b`. */
static inline double vbl_mis_weight(vbl_mis_heuristic heuristic, double a, double b)
{
    if (heuristic == VBL_MIS_BALANCE) return a + b > 0.0 ? a / (a + b) : 0.0;
    double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

#endif
