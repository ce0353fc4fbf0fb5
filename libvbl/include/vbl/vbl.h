/* libvbl public API umbrella header: include this one.
 * libvbl renders heterogeneous OpenVDB volumes (smoke, clouds, fire, fog) with virtual ray and
 * beam lights, and a volumetric path tracer as reference. C11; every header is C++-safe. */
#ifndef VBL_H
#define VBL_H

#include "vbl/vbl_core.h"
#include "vbl/vbl_volume.h"
#include "vbl/vbl_render.h"
#include "vbl/vbl_film.h"

#endif /* VBL_H */
