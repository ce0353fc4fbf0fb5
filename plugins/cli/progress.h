/* `vbl render` progress reporting (docs/readme/pipeline.md, "Progress"): a bar on stderr when it
 * is a terminal, plain lines otherwise, one JSON object per line on stdout with --progress json,
 * nothing with -q / --progress none. */
#ifndef VBL_CLI_PROGRESS_H
#define VBL_CLI_PROGRESS_H

typedef enum vbl_progress_mode {
    VBL_PROGRESS_AUTO = 0, /* bar if stderr is a TTY, else lines */
    VBL_PROGRESS_BAR = 1,
    VBL_PROGRESS_LINES = 2,
    VBL_PROGRESS_JSON = 3,
    VBL_PROGRESS_NONE = 4
} vbl_progress_mode;

/* "auto", "bar", "lines", "json", "none"; 1 on success. */
int vbl_progress_parse(const char* name, vbl_progress_mode* out);

typedef struct vbl_progress {
    vbl_progress_mode mode; /* resolved: never AUTO after vbl_progress_init */
    int frame, has_frame;
    const char* output;
    int bar_open; /* a bar line without its newline is on stderr */
} vbl_progress;

void vbl_progress_init(vbl_progress* p, vbl_progress_mode mode);
/* After a pass: `done` of `total` passes of this output (resumed passes included), the absolute
 * index of the range's first pass, seconds of this run and the estimated seconds left. */
void vbl_progress_pass(vbl_progress* p, int done, int total, int first_pass, double pass_seconds, double elapsed,
                       double eta);
void vbl_progress_checkpoint(vbl_progress* p, int done, int total);
/* A free-form note (lines/bar modes: "vbl render: <text>" on stderr; json: {"event":"message"}). */
void vbl_progress_note(vbl_progress* p, const char* text);
/* json only: {"event":"error","text":...} (the message itself always goes to stderr). */
void vbl_progress_error(vbl_progress* p, const char* text);
/* Start of one output: lines/bar modes print `text`; json: {"event":"start"} with the numbers. */
void vbl_progress_start(vbl_progress* p, const char* text, const char* method, int total, int first_pass,
                        int resumed_passes, int width, int height);
/* End of one output: status "complete", "time_limit", "interrupted", "failed", "skipped"... */
void vbl_progress_done(vbl_progress* p, const char* status, int done, int total, double elapsed, int exit_code);
/* End of the command (json only): frames rendered / failed and the exit code. */
void vbl_progress_finish(vbl_progress* p, int frames, int failed, int exit_code);
/* Ends an open bar line so that other stderr output starts on a fresh line. */
void vbl_progress_break(vbl_progress* p);

#endif
