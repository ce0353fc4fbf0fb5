/* A ray's parametric piece: the segment type of the medium interface (media/medium.h) and of the
 * samplers that pair two segments (sampling/vrl_pair.h). */
#ifndef VBL_CORE_SEGMENT_H
#define VBL_CORE_SEGMENT_H

#include "core/math.h"

/* A ray's parametric piece x(t) = origin + t direction, t in [t0, t1] (direction unit). */
typedef struct vbl_segment {
    vbl_vec3 origin, direction;
    double t0, t1;
} vbl_segment;

static inline vbl_segment vbl_segment_make(vbl_vec3 origin, vbl_vec3 direction, double t0, double t1)
{
    vbl_segment s = {origin, direction, t0, t1};
    return s;
}
static inline vbl_vec3 vbl_segment_at(const vbl_segment* s, double t) { return vbl_v3_madd(s->origin, s->direction, t); }

#endif
