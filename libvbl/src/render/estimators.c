/* Method -> estimator table. vpl and vrl plug in here (transport/vpl.h, transport/vrl.h). */
#include "transport/estimator.h"
#include "transport/pt.h"

const vbl_estimator* vbl_estimator_for(vbl_render_method method)
{
    switch (method) {
    case VBL_RENDER_PT: return &vbl_estimator_pt;
    case VBL_RENDER_VPL: return NULL; /* not implemented yet */
    case VBL_RENDER_VRL: return NULL; /* not implemented yet */
    }
    return NULL;
}
