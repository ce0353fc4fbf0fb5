/* `vbl render SCENE.json -o OUT.exr [options]`: renders a scene file to one multi-layer EXR
 * (beauty + one layer per transport class + AOVs on request) in a chosen colour space, with
 * checkpoints and an optional OCIO preview (docs/readme/render.md, docs/readme/output.md).
 * Flags: render_options.c; outputs: render_output.c; pass loop and checkpoints:
 * render_checkpoint.c. */
#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "render_cli.h"

int vbl_cmd_render(int argc, char** argv)
{
    vbl_render_args args;
    int code = vbl_render_parse_args(argc, argv, &args);
    if (code >= 0) return code;

    vbl_render_options options = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_render_method method = VBL_RENDER_PT;
    if (args.method && vbl_render_method_parse(args.method, &method)) {
        fprintf(stderr, "vbl render: --method '%s' is not one of pt, vpl, vrl, vbl\n", args.method);
        return VBL_EXIT_USAGE;
    }
    vbl_transmittance_estimator estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    if (args.transmittance && vbl_transmittance_estimator_parse(args.transmittance, &estimator)) {
        fprintf(stderr, "vbl render: --transmittance '%s' is not a transmittance estimator\n", args.transmittance);
        return VBL_EXIT_USAGE;
    }

    /* Output directories, scene hash, colour spaces: checked before any loading or rendering. */
    vbl_render_output* output = NULL;
    vbl_result r = vbl_render_output_create(&args, &output);
    if (r) return vbl_cli_fail(r);

    vbl_scene_load_options load = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    load.vdb_overrides = args.vdb;
    load.vdb_override_count = args.vdb_count;
    vbl_render_output_scene_load_options(output, &load);
    vbl_scene* scene = NULL;
    r = vbl_scene_load_ex(args.scene_path, &load, &scene);
    if (!r) r = vbl_render_output_check_scene(output, scene);
    if (r) {
        vbl_scene_release(scene);
        vbl_render_output_destroy(output);
        return vbl_cli_fail(r);
    }

    vbl_scene_render_options(scene, &options);
    if (args.method) options.method = method;
    if (args.transmittance) options.transmittance = estimator;
    if (args.passes > 0) options.passes = (int)args.passes;
    if (args.spp > 0) options.spp = (int)args.spp;
    if (args.light_paths >= 0) options.light_paths = (int)args.light_paths;
    if (args.seed >= 0) options.seed = (uint64_t)args.seed;
    if (args.time_limit >= 0.0) options.time_limit = args.time_limit;
    if (args.max_bounces != LONG_MIN) options.max_bounces = (int)args.max_bounces;
    if (args.vbl_radius0 > 0.0) options.vbl_radius0 = args.vbl_radius0;
    if (args.vbl_alpha > 0.0) options.vbl_alpha = args.vbl_alpha;
    options.threads = (int)args.threads;

    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    if (!args.quiet)
        fprintf(stderr, "vbl render: %s %dx%d, method %s, %d passes x %d spp, seed %llu\n", args.scene_path, w, h,
                vbl_render_method_name(options.method), options.passes, options.spp,
                (unsigned long long)options.seed);

    double start = vbl_render_now();
    vbl_film* film = NULL;
    const char* status = "failed";
    r = vbl_render_run(scene, &options, &args, output, &film, &status);
    int exit_code = VBL_EXIT_OK;
    if (r == VBL_ERROR_INTERRUPTED) {
        vbl_clear_error();
        exit_code = VBL_EXIT_INTERRUPTED;
        fprintf(stderr, film ? "vbl render: interrupted; writing the passes done so far\n"
                             : "vbl render: interrupted; keeping the last checkpoint\n");
    } else if (r) {
        exit_code = vbl_cli_fail(r);
    }
    if (film) {
        vbl_result wr = vbl_render_output_write_exr(output, film, &options, options.passes, status,
                                                    vbl_render_now() - start);
        if (!wr) wr = vbl_render_output_write_preview(output, film);
        if (wr) {
            exit_code = vbl_cli_fail(wr);
        } else if (!args.quiet) {
            vbl_film_stats stats;
            memset(&stats, 0, sizeof stats);
            stats.size = sizeof stats;
            vbl_film_get_stats(film, &stats);
            fprintf(stderr, "vbl render: wrote %s (%s, %d of %d passes, %.2f s, %d threads)\n", args.output, status,
                    stats.passes, options.passes, vbl_render_now() - start, stats.threads);
        }
    }
    vbl_film_release(film);
    vbl_scene_release(scene);
    vbl_render_output_destroy(output);
    return exit_code;
}
