/* The `vbl` command line: one file per sub-command, each `int vbl_cmd_NAME(int argc, char** argv)`
 * receiving argv[0] = the sub-command name. Exit codes are documented in docs/reference/cli.md. */
#ifndef VBL_CLI_H
#define VBL_CLI_H

#include <vbl/vbl.h>

/* Exit codes. */
enum {
    VBL_EXIT_OK = 0,
    VBL_EXIT_FAILURE = 1,     /* a render/computation failed */
    VBL_EXIT_USAGE = 2,       /* bad command line */
    VBL_EXIT_BAD_INPUT = 3,   /* missing/corrupt/invalid input file or scene */
    VBL_EXIT_IO = 4,          /* could not write output */
    VBL_EXIT_INTERRUPTED = 5  /* interrupted by a signal */
};

int vbl_cmd_info(int argc, char** argv);
int vbl_cmd_transmittance(int argc, char** argv);
int vbl_cmd_render(int argc, char** argv);
int vbl_cmd_preview(int argc, char** argv);
int vbl_cmd_diff(int argc, char** argv);
int vbl_cmd_merge(int argc, char** argv);
int vbl_cmd_farm(int argc, char** argv);
int vbl_cmd_options(int argc, char** argv);

/* Prints "vbl: <message>" for a failed library call and maps the result to an exit code. */
int vbl_cli_fail(vbl_result result);
/* Maps a library result to the exit code above. */
int vbl_cli_exit_code(vbl_result result);

#endif
