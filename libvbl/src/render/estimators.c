/* Method -> estimator table. vpl and vrl plug in here (transport/virtual_lights/vpl.h, transport/virtual_lights/vrl.h). */
#include "transport/common/estimator.h"
#include "transport/photon_beams/photon_beams.h"
#include "transport/path_tracing/pt.h"
#include "transport/virtual_lights/virtual_beam_lights.h"
#include "transport/virtual_lights/vpl.h"
#include "transport/virtual_lights/vrl.h"

const vbl_estimator* vbl_estimator_for(vbl_render_method method)
{
    switch (method) {
    case VBL_RENDER_PT: return &vbl_estimator_pt;
    case VBL_RENDER_VPL: return &vbl_estimator_vpl;
    case VBL_RENDER_VRL: return &vbl_estimator_vrl;
    case VBL_RENDER_VBL: return &vbl_estimator_vbl;
    case VBL_RENDER_BEAMS: return &vbl_estimator_beams;
    }
    return NULL;
}
