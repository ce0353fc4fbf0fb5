/* exploration driver (temporary) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_test_util.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "render/render_internal.h"
#include "volume_test_grid.h"

static const char* names[5] = {"pt", "vpl", "vrl", "vbl", "beams"};

int main(int argc, char** argv)
{
    double g = atof(argv[1]), scale = atof(argv[2]);
    int light = atoi(argv[3]); /* 0 distant from above, 1 point inside */
    int res = atoi(argv[4]), passes = atoi(argv[5]), K = atoi(argv[6]);
    int lp = argc > 7 ? atoi(argv[7]) : 500;
    double r0b = argc > 8 ? atof(argv[8]) : 0.0, r0v = argc > 9 ? atof(argv[9]) : 0.0;
    unsigned mask = argc > 10 ? (unsigned)strtoul(argv[10], 0, 0) : 31u;
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4, 0.3), vbl_v3(0.125, 0.125, 0.125), 40.0, res, res);
    vbl_scene* s = tt_scene(&cam);
    vbl_volume* vol = light == 3 ? tt_make_sphere(24, 1.0) : rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
    vbl_scene_add_medium(s, vol, scale, vbl_v3(0.8, 0.8, 0.8), g, NULL);
    if (light == 0) tt_add_distant(s, vbl_v3(0, 0, -1), 1.0);
    else if (light == 1) tt_add_point(s, vbl_v3(0.125, 0.125, 0.125), 10.0);
    else if (light == 2) tt_add_distant(s, vbl_v3(0.06, -1, 0.04), 1.0);
    else if (light == 3) tt_add_point(s, vbl_v3(0.05, 0.03, 0.02), 10.0);
    else tt_add_distant(s, vbl_v3(-0.06, 1, -0.04), 1.0);
    for (int m = 0; m < 5; ++m) {
        if (!(mask & (1u << m))) continue;
        vbl_render_options o = tt_options(passes, m == 0 ? 4 : 1, m == 0 ? 0 : lp, 11);
        o.method = (vbl_render_method)m;
        if (r0b > 0) o.beams.radius0 = r0b;
        if (r0v > 0) o.beam_lights.radius0 = r0v;
        tt_stats st;
        { vbl_film* f = NULL; o.passes = 1; if (vbl_render(s, &o, &f)) { printf("%s: %s\n", names[m], vbl_last_error_message()); continue; } vbl_film_release(f); o.passes = passes; }
        tt_replicate(s, vbl_estimator_for(o.method), &o, K, res / 8, &st);
        printf("%-5s direct %.5g +- %.2g  from_volume %.5g +- %.2g finite %d\n", names[m], st.image_mean[0],
               st.image_se[0], st.image_mean[1], st.image_se[1], st.finite);
        fflush(stdout);
    }
    vbl_scene_release(s);
    vt_free(vol);
    return 0;
}
