/* `vbl render` pass loop: progress lines, SIGINT/SIGTERM, --time-limit and checkpoints
 * (--checkpoint-passes N / --checkpoint-seconds S rewrite the output EXR with the film so far).
 *
 * libvbl's public API has no way yet to read the film in the middle of a render, so a checkpoint
 * stops the render through the pass callback (which hands back the film of the passes done),
 * writes it, and starts the render again with the same seed: passes are independent streams
 * (seed, pass, pixel), so the re-render reproduces the passes already done bit for bit and the
 * final image is identical to an uncheckpointed one. The cost is re-rendering the passes done at
 * every checkpoint (quadratic in the number of checkpoints); docs/readme/render.md says so. When
 * libvbl exposes a snapshot of the film inside the pass callback, only vbl_render_run changes. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "render_cli.h"

static volatile sig_atomic_t vbl_render_signalled = 0;

static void vbl_render_on_signal(int sig)
{
    (void)sig;
    vbl_render_signalled = 1;
}

double vbl_render_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

enum { VBL_STOP_NONE = 0, VBL_STOP_CHECKPOINT = 1, VBL_STOP_SIGNAL = 2, VBL_STOP_TIME_LIMIT = 3 };

typedef struct vbl_render_loop {
    const vbl_render_args* args;
    double start;      /* render start (the time limit counts from here) */
    double last_write; /* last checkpoint (or start) */
    double time_limit; /* <= 0: none */
    int done;          /* passes in the last checkpoint: re-rendered silently, never checkpointed again */
    int stop;
} vbl_render_loop;

static int vbl_render_loop_callback(const vbl_render_progress* p, void* user)
{
    vbl_render_loop* s = user;
    double now = vbl_render_now();
    if (!s->args->quiet && p->pass > s->done)
        fprintf(stderr, "vbl render: pass %d/%d  %.2f s (total %.2f s)\n", p->pass, p->passes, p->pass_seconds,
                now - s->start);
    if (vbl_render_signalled) {
        s->stop = VBL_STOP_SIGNAL;
        return 1;
    }
    if (p->pass >= p->passes || p->pass <= s->done) return 0;
    if (s->time_limit > 0.0 && now - s->start >= s->time_limit) {
        s->stop = VBL_STOP_TIME_LIMIT;
        return 1;
    }
    if ((s->args->checkpoint_passes > 0 && p->pass - s->done >= s->args->checkpoint_passes) ||
        (s->args->checkpoint_seconds > 0.0 && now - s->last_write >= s->args->checkpoint_seconds)) {
        s->stop = VBL_STOP_CHECKPOINT;
        return 1;
    }
    return 0;
}

static int vbl_film_passes(const vbl_film* film)
{
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    return stats.passes;
}

static vbl_result vbl_render_loop_run(const vbl_scene* scene, const vbl_render_options* options,
                                      vbl_render_loop* s, vbl_render_output* output, vbl_film** out_film,
                                      const char** status)
{
    vbl_render_options opts = *options;
    opts.time_limit = 0.0; /* counted here, across checkpoint restarts */
    opts.callback = vbl_render_loop_callback;
    opts.callback_user_data = s;
    for (;;) {
        s->stop = VBL_STOP_NONE;
        vbl_film* film = NULL;
        vbl_result r = vbl_render(scene, &opts, &film);
        if (r == VBL_SUCCESS) {
            *status = "complete";
            *out_film = film;
            return VBL_SUCCESS;
        }
        if (r != VBL_ERROR_INTERRUPTED || !film) return r;
        int passes = vbl_film_passes(film);
        if (s->stop == VBL_STOP_TIME_LIMIT) {
            vbl_clear_error();
            *status = "time_limit";
            *out_film = film;
            return VBL_SUCCESS;
        }
        if (s->stop == VBL_STOP_SIGNAL) {
            *status = "interrupted";
            if (passes > s->done) *out_film = film; /* else the checkpoint on disk has more passes: keep it */
            else vbl_film_release(film);
            return VBL_ERROR_INTERRUPTED;
        }
        vbl_clear_error();
        r = vbl_render_output_write_exr(output, film, options, options->passes, "checkpoint",
                                        vbl_render_now() - s->start);
        vbl_film_release(film);
        if (r) return r;
        s->done = passes;
        s->last_write = vbl_render_now();
        if (!s->args->quiet)
            fprintf(stderr, "vbl render: checkpoint %s (%d of %d passes)\n", s->args->output, passes,
                    options->passes);
    }
}

vbl_result vbl_render_run(const vbl_scene* scene, const vbl_render_options* options, const vbl_render_args* args,
                          vbl_render_output* output, vbl_film** out_film, const char** status)
{
    *out_film = NULL;
    *status = "failed";
    vbl_render_loop s;
    memset(&s, 0, sizeof s);
    s.args = args;
    s.start = s.last_write = vbl_render_now();
    s.time_limit = options->time_limit;

    struct sigaction sa, old_int, old_term;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = vbl_render_on_signal;
    sigemptyset(&sa.sa_mask);
    vbl_render_signalled = 0;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    vbl_result r = vbl_render_loop_run(scene, options, &s, output, out_film, status);
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    return r;
}
