/* `vbl render` internals shared by cmd_render.c (orchestration), render_options.c (flags),
 * render_output.c (EXR layers, colour, metadata, preview) and render_checkpoint.c (the pass loop
 * with checkpoints and interruption). Not a public header. */
#ifndef VBL_CLI_RENDER_CLI_H
#define VBL_CLI_RENDER_CLI_H

#include "cli.h"
#include "progress.h"
#include "vbl_exr.h"

#define VBL_RENDER_CLI_MAX_VDB 8
#define VBL_RENDER_CLI_MAX_OPTIONS 128

/* The command line of `vbl render`, as parsed (negative numbers: not given). */
typedef struct vbl_render_args {
    const char* scene_path;
    const char* output;
    const char* preview;
    const char* vdb[VBL_RENDER_CLI_MAX_VDB];
    int vdb_count;
    /* The render options' flags (options table: --passes, --vbl-alpha, ...), by table index, as
     * given and already checked by vbl_render_option_set_strict; NULL: not given. */
    const char* option_values[VBL_RENDER_CLI_MAX_OPTIONS];
    int quiet;
    /* EXR storage */
    int half_all;                 /* --half: every colour layer (beauty, transport, variance) as HALF */
    const char* half_layers;      /* --half-layers LIST: these layers as HALF ("beauty" = the R,G,B,A) */
    const char* aovs;             /* --aov LIST: z, samples, variance, all */
    int aov_z, aov_samples, aov_variance;
    int compression;              /* vbl_exr_compression; -1: default (zip) */
    int tiled, tile_size;
    /* colour */
    const char* output_space;     /* NULL: the config's scene_linear space */
    const char* config;           /* NULL: $OCIO, else the shipped config */
    const char* display, *view;
    double exposure;
    /* checkpoints */
    long checkpoint_passes;       /* 0: none */
    double checkpoint_seconds;    /* 0: none */
    /* pipeline (docs/readme/pipeline.md) */
    const char* preset;           /* --preset preview|production|final; NULL: none */
    int progress_mode;            /* vbl_progress_mode (progress.h); -q: none */
    const char* frames;           /* --frames SPEC; NULL: no frame loop */
    int keep_going;               /* --keep-going: later frames still render after a failed one */
    int resume;                   /* --resume: continue from OUT.exr if it is a compatible checkpoint */
    long pass_first, pass_last;   /* --pass-range A-B (inclusive, absolute); -1: not given */
    /* shot controls (docs/readme/render.md, "Camera") */
    const char* camera;           /* --camera NAME|FILE.json: a camera of the scene's "cameras" or a file */
    int width, height;            /* --resolution WxH; 0: the camera's */
    int animated_seed;            /* --animated-seed: frame f renders with seed + f * 0x9E3779B97F4A7C15 */
    /* set per frame by cmd_render.c (the paths above then hold the frame's file names) */
    int frame, has_frame;
} vbl_render_args;

/* Parses argv (argv[0] = "render"). Returns -1 to go on, else the exit code to return (help
 * printed, or a usage error already reported on stderr). */
int vbl_render_parse_args(int argc, char** argv, vbl_render_args* args);

/* Everything needed to write the outputs, prepared before rendering so that a bad colour space,
 * an unwritable directory or an unreadable scene fails before any work is done. */
typedef struct vbl_render_output vbl_render_output;

/* Checks the output directories, hashes the scene file, opens the OCIO config and resolves the
 * output colour space (its conversion matrix from scene_linear and its chromaticities). */
vbl_result vbl_render_output_create(const vbl_render_args* args, vbl_render_output** out);
void vbl_render_output_destroy(vbl_render_output* output);
/* Sets load->convert_color so that a scene's "color_space" colours are converted to the
 * config's scene_linear space (the film's) through OCIO (docs/readme/render.md). */
void vbl_render_output_scene_load_options(vbl_render_output* output, vbl_scene_load_options* load);
/* Fails (VBL_ERROR_SCENE) when the loaded scene's color_space is not in the config. */
vbl_result vbl_render_output_check_scene(const vbl_render_output* output, const vbl_scene* scene);

/* Resume: `base` (a compatible checkpoint of `passes` passes starting at the absolute pass
 * `first_pass`, retained) is merged, weighted by pass count, into every EXR written from now on
 * (merge.h); the metadata then counts the base's passes too. */
void vbl_render_output_set_base(vbl_render_output* output, vbl_exr_image* base, int passes, int first_pass,
                                double seconds);
/* Resume: checks that the EXR at args->output can be continued by a render with `options`
 * (identity attributes, resolution, first pass, AOV channels). 0 if compatible (*out_passes
 * receives its passes done), else a VBL_ERROR_SCENE-class error naming the file and field. */
vbl_result vbl_render_output_check_resume(vbl_render_output* output, const vbl_scene* scene,
                                          const vbl_render_options* options, const vbl_exr_image* image);
/* The scene's resolved media paths, recorded as vbl:media (call once the scene is loaded). */
void vbl_render_output_set_scene(vbl_render_output* output, const vbl_scene* scene);

/* Writes the EXR (`status`: "complete", "checkpoint", "interrupted", "time_limit") with the
 * options actually used and the wall-clock seconds since the command started. */
vbl_result vbl_render_output_write_exr(vbl_render_output* output, const vbl_film* film,
                                       const vbl_render_options* options, int passes_requested,
                                       const char* status, double wall_seconds);
/* Writes the --preview PNG (no-op without --preview). */
vbl_result vbl_render_output_write_preview(vbl_render_output* output, const vbl_film* film);

/* Runs the progressive render with the command's checkpoints (writing them through `output`),
 * progress lines and SIGINT/SIGTERM handling. On success or interruption *out_film receives the
 * film and *status its status string; returns the render's result (VBL_ERROR_INTERRUPTED with a
 * film after a signal). */
vbl_result vbl_render_run(const vbl_scene* scene, const vbl_render_options* options, const vbl_render_args* args,
                          vbl_render_output* output, vbl_progress* progress, int base_passes, int total_passes,
                          vbl_film** out_film, const char** status);

/* SIGINT/SIGTERM handling for the whole command: install (1) / restore (0). */
void vbl_render_signals(int install);
/* 1 after SIGINT/SIGTERM since vbl_render_signals(1) (the frame loop stops). */
int vbl_render_interrupted(void);
/* The cancel flag the signal handler sets (for vbl_scene_load_options.cancel too). */
const volatile int* vbl_render_cancel_pointer(void);

/* Monotonic clock in seconds. */
double vbl_render_now(void);
/* Seconds since this process started (Linux /proc/self/stat; 0 when unknown). */
double vbl_process_seconds(void);

#endif
