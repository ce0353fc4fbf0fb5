/* `vbl render` pass loop: progress, SIGINT/SIGTERM, --time-limit and checkpoints
 * (--checkpoint-passes N / --checkpoint-seconds S rewrite the output EXR with the film so far).
 *
 * Checkpoints are written from inside the pass callback with vbl_render_snapshot (the film of
 * the passes done, without stopping the render), so checkpointing costs one EXR write and never
 * changes the final image. A resumed render (--resume) merges the checkpoint it continues into
 * every file it writes (render_output.c), so the file on disk always holds every pass done. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "render_cli.h"

static volatile sig_atomic_t vbl_render_signalled = 0;
/* Set by the first signal's handler, atomically: SIGINT and SIGTERM delivered at once can run
 * their handlers in two threads together (the render's OpenMP workers take signals too), and a
 * plain read-then-set let both see "first" and neither abort (test_pipeline_robust's
 * test_second_sigint_aborts failed once in CI that way). A lock-free atomic_flag is
 * async-signal-safe (C11 7.17.8). */
static atomic_flag vbl_render_signal_seen = ATOMIC_FLAG_INIT;
/* The library's cancel flag (vbl_render_options.cancel): the pass in progress stops at its next
 * pixel and is dropped, so SIGINT/SIGTERM end a render within a pixel's time, not a pass's. */
static volatile int vbl_render_cancel_flag = 0;
static struct sigaction vbl_render_old_int, vbl_render_old_term;

static void vbl_render_on_signal(int sig)
{
    (void)sig;
    /* A second signal aborts at once. Outputs are written to a temporary name and renamed, so the
     * output stays the last complete file (a temporary ".<name>.tmp-XXXXXX" may remain). */
    if (atomic_flag_test_and_set(&vbl_render_signal_seen)) _exit(VBL_EXIT_INTERRUPTED);
    vbl_render_signalled = 1;
    vbl_render_cancel_flag = 1;
}

void vbl_render_signals(int install)
{
    if (install) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = vbl_render_on_signal;
        sigemptyset(&sa.sa_mask);
        vbl_render_signalled = 0;
        atomic_flag_clear(&vbl_render_signal_seen);
        vbl_render_cancel_flag = 0;
        sigaction(SIGINT, &sa, &vbl_render_old_int);
        sigaction(SIGTERM, &sa, &vbl_render_old_term);
    } else {
        sigaction(SIGINT, &vbl_render_old_int, NULL);
        sigaction(SIGTERM, &vbl_render_old_term, NULL);
    }
}

int vbl_render_interrupted(void) { return vbl_render_signalled != 0; }

const volatile int* vbl_render_cancel_pointer(void) { return &vbl_render_cancel_flag; }

double vbl_render_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

enum { VBL_STOP_NONE = 0, VBL_STOP_SIGNAL = 1, VBL_STOP_TIME_LIMIT = 2 };

typedef struct vbl_render_loop {
    const vbl_render_args* args;
    const vbl_render_options* options; /* as given (first_pass, passes of this run) */
    vbl_render_output* output;
    vbl_progress* progress;
    int base_passes;   /* passes of the checkpoint being resumed (0: none) */
    int total_passes;  /* passes of the whole output: base + this run */
    double start;      /* this run's start (the time limit counts from here) */
    double last_write; /* last checkpoint (or start) */
    int last_written;  /* passes in the last checkpoint */
    int stop;
} vbl_render_loop;

static vbl_result vbl_render_write_checkpoint(vbl_render_loop* s, const vbl_render_progress* p)
{
    vbl_film* film = NULL;
    vbl_result r = vbl_render_snapshot(p, &film);
    if (!r)
        r = vbl_render_output_write_exr(s->output, film, s->options, s->total_passes, "checkpoint",
                                        vbl_render_now() - s->start);
    vbl_film_release(film);
    if (r) return r;
    s->last_written = p->pass;
    s->last_write = vbl_render_now();
    vbl_progress_checkpoint(s->progress, s->base_passes + p->pass, s->total_passes);
    return VBL_SUCCESS;
}

static int vbl_render_loop_callback(const vbl_render_progress* p, void* user)
{
    vbl_render_loop* s = user;
    double now = vbl_render_now(), elapsed = now - s->start;
    double eta = p->pass > 0 ? elapsed / p->pass * (p->passes - p->pass) : 0.0;
    vbl_progress_pass(s->progress, s->base_passes + p->pass, s->total_passes, s->options->first_pass - s->base_passes,
                      p->pass_seconds, elapsed, eta);
    if (vbl_render_signalled) {
        s->stop = VBL_STOP_SIGNAL;
        return 1;
    }
    if (p->pass >= p->passes) return 0;
    if (s->options->time_limit > 0.0 && elapsed >= s->options->time_limit && p->pass >= s->options->min_passes) {
        s->stop = VBL_STOP_TIME_LIMIT;
        return 1;
    }
    if ((s->args->checkpoint_passes > 0 && p->pass - s->last_written >= s->args->checkpoint_passes) ||
        (s->args->checkpoint_seconds > 0.0 && now - s->last_write >= s->args->checkpoint_seconds)) {
        vbl_result r = vbl_render_write_checkpoint(s, p);
        if (r) {
            /* A failed checkpoint (disk full for a moment, a read-only mount) is a warning: the
             * render goes on, the next checkpoint or the final write tries again. */
            char note[2200];
            snprintf(note, sizeof note, "warning: checkpoint not written (%s); rendering continues",
                     vbl_last_error_message());
            vbl_clear_error();
            vbl_progress_note(s->progress, note);
            s->last_write = vbl_render_now();
            s->last_written = p->pass;
        }
    }
    return 0;
}

vbl_result vbl_render_run(const vbl_scene* scene, const vbl_render_options* options, const vbl_render_args* args,
                          vbl_render_output* output, vbl_progress* progress, int base_passes, int total_passes,
                          vbl_film** out_film, const char** status)
{
    *out_film = NULL;
    *status = "failed";
    vbl_render_loop s;
    memset(&s, 0, sizeof s);
    s.args = args;
    s.options = options;
    s.output = output;
    s.progress = progress;
    s.base_passes = base_passes;
    s.total_passes = total_passes;
    s.start = s.last_write = vbl_render_now();

    vbl_render_options opts = *options;
    /* The library stops a pass that runs past the limit (after the first) and drops it; the
     * callback stops between passes and writes the checkpoints. */
    opts.time_limit = options->time_limit;
    opts.callback = vbl_render_loop_callback;
    opts.callback_user_data = &s;
    opts.cancel = &vbl_render_cancel_flag;
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &opts, &film);
    if (r == VBL_SUCCESS) {
        vbl_film_stats stats;
        memset(&stats, 0, sizeof stats);
        stats.size = sizeof stats;
        vbl_film_get_stats(film, &stats);
        /* a signal after the last pass: the caller sees vbl_render_interrupted() */
        *status = stats.time_limited ? "time_limit" : "complete";
        *out_film = film;
        return VBL_SUCCESS;
    }
    if (r != VBL_ERROR_INTERRUPTED || !film) {
        vbl_film_release(film);
        return r;
    }
    switch (s.stop) {
    case VBL_STOP_TIME_LIMIT:
        vbl_clear_error();
        *status = "time_limit";
        *out_film = film;
        return VBL_SUCCESS;
    default:
        *status = "interrupted";
        *out_film = film;
        return VBL_ERROR_INTERRUPTED;
    }
}
