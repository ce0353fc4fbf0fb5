/* `vbl render SCENE.json -o OUT.exr [options]`: renders a scene file to one multi-layer EXR
 * (beauty + one layer per transport class + AOVs on request) in a chosen colour space, with
 * checkpoints and an optional OCIO preview (docs/readme/render.md, docs/readme/output.md), over
 * frame ranges, pass ranges and resumed checkpoints (docs/readme/pipeline.md).
 * Flags: render_options.c; outputs: render_output.c; pass loop and checkpoints:
 * render_checkpoint.c; frames: frames.c; progress: progress.c. */
#define _POSIX_C_SOURCE 200809L
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "frames.h"
#include "render_cli.h"

/* Builds the render options: the scene's render block, then the preset, then the flags (checked
 * by the options table's validator while parsing). */
static int vbl_render_make_options(const vbl_render_args* args, const vbl_scene* scene, vbl_render_options* options)
{
    vbl_scene_render_options(scene, options);
    if (args->preset && vbl_render_options_apply_preset(args->preset, options)) {
        fprintf(stderr, "vbl render: --preset '%s' is not one of preview, production, final\n", args->preset);
        return VBL_EXIT_USAGE;
    }
    for (int i = 0; i < vbl_render_option_count(); ++i)
        if (args->option_values[i] &&
            vbl_render_option_set_strict(options, vbl_render_option_desc(i)->name, args->option_values[i]))
            return vbl_cli_fail(VBL_ERROR_INVALID_ARGUMENT);
    if (args->animated_seed && args->has_frame) /* a fresh pattern per frame (Cycles' animated seed) */
        options->seed += (uint64_t)(int64_t)args->frame * 0x9E3779B97F4A7C15ull;
    if (args->pass_first >= 0) {
        options->first_pass = (int)args->pass_first;
        options->passes = (int)(args->pass_last - args->pass_first + 1);
    }
    return -1;
}

/* Reports a failed library call: "vbl: <message>" on stderr (and a JSON message line). */
static int vbl_render_fail(vbl_progress* progress, vbl_result r)
{
    vbl_progress_break(progress);
    if (progress->mode == VBL_PROGRESS_JSON) {
        const char* message = vbl_last_error_message();
        vbl_progress_error(progress, message && message[0] ? message : vbl_result_name(r));
    }
    return vbl_cli_fail(r);
}

/* One output file (one frame). */
static int vbl_render_one(const vbl_render_args* args, vbl_progress* progress)
{
    /* --time-limit counts from here, loading included; the first frame's from the process start */
    static int first_frame = 1;
    const double frame_start = vbl_render_now() - (first_frame ? vbl_process_seconds() : 0.0);
    first_frame = 0;
    vbl_render_output* output = NULL;
    vbl_result r = vbl_render_output_create(args, &output);
    if (r) return vbl_render_fail(progress, r);

    vbl_scene_load_options load = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    load.vdb_overrides = args->vdb;
    load.vdb_override_count = args->vdb_count;
    load.frame = args->frame;
    load.use_frame = args->has_frame;
    load.camera = args->camera;
    load.width = args->width;
    load.height = args->height;
    load.cancel = vbl_render_cancel_pointer(); /* SIGINT/SIGTERM while loading media */
    vbl_render_output_scene_load_options(output, &load);
    vbl_scene* scene = NULL;
    r = vbl_scene_load_ex(args->scene_path, &load, &scene);
    if (!r) r = vbl_render_output_check_scene(output, scene);
    if (r) {
        vbl_scene_release(scene);
        vbl_render_output_destroy(output);
        return vbl_render_fail(progress, r);
    }
    vbl_render_output_set_scene(output, scene);
    if (vbl_scene_light_count(scene) == 0 && !vbl_scene_has_emission(scene))
        fprintf(stderr, "vbl render: warning: %s has no lights and no emissive media: the image will be black\n",
                args->scene_path);

    vbl_render_options options = VBL_RENDER_OPTIONS_DEFAULT;
    int code = vbl_render_make_options(args, scene, &options);
    const int total = options.passes, range_first = options.first_pass;
    int base_passes = 0;
    vbl_exr_image* base = NULL;
    if (code < 0 && args->resume && access(args->output, F_OK) == 0) {
        r = vbl_exr_read(args->output, &base);
        if (r) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s", vbl_last_error_message());
            r = vbl_report_error(VBL_ERROR_CORRUPT_FILE, "cannot resume from %s: %s", args->output, msg);
        }
        if (!r) r = vbl_render_output_check_resume(output, scene, &options, base);
        if (r) {
            code = vbl_render_fail(progress, r);
        } else {
            base_passes = atoi(vbl_exr_image_attribute(base, "vbl:passes", NULL));
            const char* seconds = vbl_exr_image_attribute(base, "vbl:render_seconds", NULL);
            if (base_passes >= total) {
                char note[4096];
                snprintf(note, sizeof note, "%s already holds %d of %d passes; nothing to render", args->output,
                         base_passes, total);
                vbl_progress_note(progress, note);
                vbl_progress_done(progress, "complete", base_passes, total, 0.0, VBL_EXIT_OK);
                code = VBL_EXIT_OK;
            } else {
                vbl_render_output_set_base(output, base, base_passes, range_first, seconds ? atof(seconds) : 0.0);
                options.first_pass += base_passes;
                options.passes -= base_passes;
            }
        }
    }
    if (code >= 0) {
        if (base) vbl_exr_image_release(base);
        vbl_scene_release(scene);
        vbl_render_output_destroy(output);
        return code;
    }

    char limits[4096];
    if (vbl_render_limits(scene, &options, limits, sizeof limits) > 0) /* documented limits: render.md */
        for (char* line = strtok(limits, "\n"); line; line = strtok(NULL, "\n"))
            fprintf(stderr, "vbl render: warning: %s\n", line);

    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    char note[4096];
    if (base_passes > 0)
        snprintf(note, sizeof note, "%s %dx%d, method %s: resuming %s at pass %d of %d (%d done), %d spp, seed %llu",
                 args->scene_path, w, h, vbl_render_method_name(options.method), args->output, base_passes + 1, total,
                 base_passes, options.spp, (unsigned long long)options.seed);
    else
        snprintf(note, sizeof note, "%s %dx%d, method %s, %d passes x %d spp, seed %llu%s", args->scene_path, w, h,
                 vbl_render_method_name(options.method), total, options.spp, (unsigned long long)options.seed,
                 range_first > 0 || args->pass_first >= 0 ? " (pass range)" : "");
    vbl_progress_start(progress, note, vbl_render_method_name(options.method), total, range_first, base_passes, w, h);

    if (vbl_render_interrupted()) { /* a signal while loading: nothing rendered, nothing written */
        vbl_progress_done(progress, "interrupted", base_passes, total, 0.0, VBL_EXIT_INTERRUPTED);
        if (base) vbl_exr_image_release(base);
        vbl_scene_release(scene);
        vbl_render_output_destroy(output);
        return VBL_EXIT_INTERRUPTED;
    }
    double start = vbl_render_now();
    vbl_film* film = NULL;
    const char* status = "failed";
    /* the library's clock starts at vbl_render: give it what loading left of the limit (the EXR
     * records the limit as given) */
    vbl_render_options run_options = options;
    if (options.time_limit > 0.0) {
        double left = options.time_limit - (start - frame_start);
        run_options.time_limit = left > 1e-6 ? left : 1e-6;
    }
    r = vbl_render_run(scene, &run_options, args, output, progress, base_passes, total, &film, &status);
    int exit_code = VBL_EXIT_OK;
    if (r == VBL_ERROR_INTERRUPTED && !film && !vbl_render_interrupted()) {
        /* the time limit ended the first pass: the library's message says where; nothing written */
        exit_code = vbl_render_fail(progress, r);
    } else if (r == VBL_ERROR_INTERRUPTED) {
        vbl_clear_error();
        exit_code = VBL_EXIT_INTERRUPTED;
        vbl_progress_note(progress, film ? "interrupted; writing the passes done so far"
                                         : "interrupted; keeping the last checkpoint");
    } else if (r) {
        exit_code = vbl_render_fail(progress, r);
    }
    int done = base_passes;
    if (film) {
        vbl_result wr = vbl_render_output_write_exr(output, film, &options, total, status, vbl_render_now() - start);
        if (!wr) wr = vbl_render_output_write_preview(output, film);
        vbl_film_stats stats;
        memset(&stats, 0, sizeof stats);
        stats.size = sizeof stats;
        vbl_film_get_stats(film, &stats);
        done += stats.passes;
        if (wr) {
            exit_code = vbl_render_fail(progress, wr);
        } else {
            snprintf(note, sizeof note, "wrote %s (%s, %d of %d passes, %.2f s, %d threads)", args->output, status,
                     done, total, vbl_render_now() - start, stats.threads);
            vbl_progress_note(progress, note);
            if (stats.hybrid) { /* render.hybrid: the plan as rendered (also the EXR's vbl:hybrid) */
                size_t n = (size_t)snprintf(note, sizeof note, "hybrid: pt renders");
                int any = 0;
                for (int c = 0; c < VBL_CLASS_COUNT && n < sizeof note; ++c)
                    if (stats.hybrid_pt_classes & (1 << c)) {
                        n += (size_t)snprintf(note + n, sizeof note - n, "%s%s", any ? "," : " ",
                                              vbl_transport_class_name((vbl_transport_class)c));
                        any = 1;
                    }
                if (n < sizeof note)
                    snprintf(note + n, sizeof note - n, "%s with %d sample(s) per %s sample (%s)", any ? "" : " nothing",
                             stats.hybrid_pt_spp, vbl_render_method_name(stats.method),
                             stats.hybrid == VBL_HYBRID_AUTO ? "auto" : "classes");
                vbl_progress_note(progress, note);
            }
        }
    }
    vbl_progress_done(progress, exit_code ? (exit_code == VBL_EXIT_INTERRUPTED ? "interrupted" : "failed") : status,
                      done, total, vbl_render_now() - start, exit_code);
    vbl_film_release(film);
    if (base) vbl_exr_image_release(base);
    vbl_scene_release(scene);
    vbl_render_output_destroy(output);
    return exit_code;
}

int vbl_cmd_render(int argc, char** argv)
{
    vbl_render_args args;
    int code = vbl_render_parse_args(argc, argv, &args);
    if (code >= 0) return code;

    if (args.preset) {
        vbl_render_options probe = VBL_RENDER_OPTIONS_DEFAULT;
        if (vbl_render_options_apply_preset(args.preset, &probe)) {
            vbl_clear_error();
            fprintf(stderr, "vbl render: --preset '%s' is not one of preview, production, final\n", args.preset);
            return VBL_EXIT_USAGE;
        }
    }

    int* frames = NULL;
    int frame_count = 0;
    if (args.frames) {
        char err[512];
        frame_count = vbl_frames_parse(args.frames, &frames, err, sizeof err);
        if (frame_count <= 0) {
            fprintf(stderr, "vbl render: %s\n", err);
            return VBL_EXIT_USAGE;
        }
        if (frame_count > 1 && !vbl_frame_path_has_pattern(args.output)) {
            fprintf(stderr, "vbl render: -o '%s' needs a frame pattern (#### or %%04d) to render %d frames\n",
                    args.output, frame_count);
            free(frames);
            return VBL_EXIT_USAGE;
        }
        if (frame_count > 1 && args.preview && !vbl_frame_path_has_pattern(args.preview)) {
            fprintf(stderr, "vbl render: --preview '%s' needs a frame pattern (#### or %%04d) to render %d frames\n",
                    args.preview, frame_count);
            free(frames);
            return VBL_EXIT_USAGE;
        }
    } else if (vbl_frame_path_has_pattern(args.output) || vbl_frame_path_has_pattern(args.preview)) {
        fprintf(stderr, "vbl render: '%s' has a frame pattern (#### or %%d) but no --frames was given\n",
                vbl_frame_path_has_pattern(args.output) ? args.output : args.preview);
        return VBL_EXIT_USAGE;
    }

    vbl_progress progress;
    vbl_progress_init(&progress, (vbl_progress_mode)args.progress_mode);
    vbl_render_signals(1);
    int failed = 0, rendered = 0;
    code = VBL_EXIT_OK;
    for (int i = 0; i < (frame_count > 0 ? frame_count : 1); ++i) {
        if (vbl_render_interrupted()) {
            code = VBL_EXIT_INTERRUPTED;
            break;
        }
        vbl_render_args fa = args;
        char output[4096], preview[4096];
        if (frame_count > 0) {
            fa.frame = frames[i];
            fa.has_frame = 1;
            if (vbl_frame_path_format(args.output, fa.frame, output, sizeof output) ||
                (args.preview && vbl_frame_path_format(args.preview, fa.frame, preview, sizeof preview))) {
                fprintf(stderr, "vbl render: bad frame pattern in '%s' (use #### or %%04d)\n",
                        args.preview ? args.preview : args.output);
                code = VBL_EXIT_USAGE;
                break;
            }
            fa.output = output;
            if (args.preview) fa.preview = preview;
        }
        progress.frame = fa.frame;
        progress.has_frame = fa.has_frame;
        progress.output = fa.output;
        int frame_code = vbl_render_one(&fa, &progress);
        ++rendered;
        if (frame_code == VBL_EXIT_OK && vbl_render_interrupted()) frame_code = VBL_EXIT_INTERRUPTED;
        if (frame_code != VBL_EXIT_OK) {
            ++failed;
            if (code == VBL_EXIT_OK || frame_code == VBL_EXIT_INTERRUPTED) code = frame_code;
            if (frame_code == VBL_EXIT_INTERRUPTED || !args.keep_going) break;
        }
    }
    vbl_render_signals(0);
    progress.output = NULL;
    progress.has_frame = 0;
    if (frame_count > 1 && failed && progress.mode != VBL_PROGRESS_NONE && progress.mode != VBL_PROGRESS_JSON)
        fprintf(stderr, "vbl render: %d of %d frames failed%s\n", failed, frame_count,
                rendered < frame_count ? " (stopped; --keep-going renders the others)" : "");
    vbl_progress_finish(&progress, rendered, failed, code);
    free(frames);
    return code;
}
