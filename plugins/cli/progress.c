/* Progress reporting for `vbl render` (progress.h). JSON lines go to stdout, flushed per line;
 * human-readable progress goes to stderr. */
#define _POSIX_C_SOURCE 200809L
#include "progress.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

int vbl_progress_parse(const char* name, vbl_progress_mode* out)
{
    static const char* const names[5] = {"auto", "bar", "lines", "json", "none"};
    for (int i = 0; i < 5; ++i)
        if (!strcmp(name, names[i])) {
            *out = (vbl_progress_mode)i;
            return 1;
        }
    return 0;
}

void vbl_progress_init(vbl_progress* p, vbl_progress_mode mode)
{
    memset(p, 0, sizeof *p);
    if (mode == VBL_PROGRESS_AUTO) mode = isatty(STDERR_FILENO) ? VBL_PROGRESS_BAR : VBL_PROGRESS_LINES;
    p->mode = mode;
}

static void vbl_progress_json_string(const char* s)
{
    fputc('"', stdout);
    for (; s && *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') printf("\\%c", c);
        else if (c < 0x20) printf("\\u%04x", c);
        else fputc(c, stdout);
    }
    fputc('"', stdout);
}

/* {"event":"EVENT"[,"frame":F][,"output":"..."] -- the caller adds fields and the closing brace. */
static void vbl_progress_json_open(const vbl_progress* p, const char* event)
{
    printf("{\"event\":\"%s\"", event);
    if (p->has_frame) printf(",\"frame\":%d", p->frame);
    if (p->output) {
        printf(",\"output\":");
        vbl_progress_json_string(p->output);
    }
}

static void vbl_progress_json_close(void)
{
    printf("}\n");
    fflush(stdout);
}

void vbl_progress_break(vbl_progress* p)
{
    if (p->bar_open) {
        fputc('\n', stderr);
        p->bar_open = 0;
    }
}

static void vbl_progress_prefix(const vbl_progress* p)
{
    fprintf(stderr, "vbl render: ");
    if (p->has_frame) fprintf(stderr, "frame %d: ", p->frame);
}

void vbl_progress_pass(vbl_progress* p, int done, int total, int first_pass, double pass_seconds, double elapsed,
                       double eta)
{
    switch (p->mode) {
    case VBL_PROGRESS_JSON:
        vbl_progress_json_open(p, "pass");
        printf(",\"pass\":%d,\"passes\":%d,\"first_pass\":%d,\"pass_seconds\":%.3f,\"elapsed\":%.3f,\"eta\":%.3f", done,
               total, first_pass, pass_seconds, elapsed, eta);
        vbl_progress_json_close();
        break;
    case VBL_PROGRESS_LINES:
        vbl_progress_prefix(p);
        fprintf(stderr, "pass %d/%d  %.2f s (total %.2f s, about %.1f s left)\n", done, total, pass_seconds, elapsed,
                eta);
        break;
    case VBL_PROGRESS_BAR: {
        enum { WIDTH = 30 };
        int filled = total > 0 ? (int)((long long)WIDTH * done / total) : WIDTH;
        char bar[WIDTH + 1];
        for (int i = 0; i < WIDTH; ++i) bar[i] = i < filled ? '#' : '.';
        bar[WIDTH] = 0;
        fprintf(stderr, "\r");
        vbl_progress_prefix(p);
        fprintf(stderr, "[%s] %d/%d passes  %.1f s  eta %.1f s ", bar, done, total, elapsed, eta);
        fflush(stderr);
        p->bar_open = 1;
        break;
    }
    default: break;
    }
}

void vbl_progress_checkpoint(vbl_progress* p, int done, int total)
{
    if (p->mode == VBL_PROGRESS_JSON) {
        vbl_progress_json_open(p, "checkpoint");
        printf(",\"pass\":%d,\"passes\":%d", done, total);
        vbl_progress_json_close();
    } else if (p->mode == VBL_PROGRESS_LINES) {
        vbl_progress_prefix(p);
        fprintf(stderr, "checkpoint %s (%d of %d passes)\n", p->output ? p->output : "", done, total);
    }
}

void vbl_progress_note(vbl_progress* p, const char* text)
{
    if (p->mode == VBL_PROGRESS_NONE) return;
    if (p->mode == VBL_PROGRESS_JSON) {
        vbl_progress_json_open(p, "message");
        printf(",\"text\":");
        vbl_progress_json_string(text);
        vbl_progress_json_close();
        return;
    }
    vbl_progress_break(p);
    vbl_progress_prefix(p);
    fprintf(stderr, "%s\n", text);
}

void vbl_progress_error(vbl_progress* p, const char* text)
{
    if (p->mode != VBL_PROGRESS_JSON) return;
    vbl_progress_json_open(p, "error");
    printf(",\"text\":");
    vbl_progress_json_string(text);
    vbl_progress_json_close();
}

void vbl_progress_start(vbl_progress* p, const char* text, const char* method, int total, int first_pass,
                        int resumed_passes, int width, int height)
{
    if (p->mode != VBL_PROGRESS_JSON) {
        vbl_progress_note(p, text);
        return;
    }
    vbl_progress_json_open(p, "start");
    printf(",\"method\":");
    vbl_progress_json_string(method);
    printf(",\"passes\":%d,\"first_pass\":%d,\"resumed_passes\":%d,\"width\":%d,\"height\":%d", total,
           first_pass, resumed_passes, width, height);
    vbl_progress_json_close();
}

void vbl_progress_done(vbl_progress* p, const char* status, int done, int total, double elapsed, int exit_code)
{
    if (p->mode == VBL_PROGRESS_JSON) {
        vbl_progress_json_open(p, "done");
        printf(",\"status\":");
        vbl_progress_json_string(status);
        printf(",\"pass\":%d,\"passes\":%d,\"elapsed\":%.3f,\"exit_code\":%d", done, total, elapsed, exit_code);
        vbl_progress_json_close();
    } else {
        vbl_progress_break(p);
    }
}

void vbl_progress_finish(vbl_progress* p, int frames, int failed, int exit_code)
{
    if (p->mode != VBL_PROGRESS_JSON) return;
    printf("{\"event\":\"end\",\"frames\":%d,\"failed\":%d,\"status\":\"%s\",\"exit_code\":%d}\n", frames, failed,
           exit_code == 0 ? "ok" : (exit_code == 5 ? "interrupted" : "failed"), exit_code);
    fflush(stdout);
}
