/* `vbl`: entry point, --help/--version and sub-command dispatch. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

typedef struct vbl_cli_command {
    const char* name;
    int (*run)(int argc, char** argv);
    const char* summary;
} vbl_cli_command;

static const vbl_cli_command vbl_cli_commands[] = {
    {"info", vbl_cmd_info, "describe the grids of a .vdb/.nvdb file"},
    {"transmittance", vbl_cmd_transmittance, "render a transmittance image of a volume"},
    {"render", vbl_cmd_render, "render a scene file to a multi-layer EXR"},
    {"preview", vbl_cmd_preview, "write a PNG of an EXR layer through an OCIO display/view"},
    {"diff", vbl_cmd_diff, "per-layer error (rMAE, RMSE, max) of an EXR against a reference"},
    {"merge", vbl_cmd_merge, "combine EXRs of disjoint pass ranges (vbl render --pass-range) into one"},
    {"farm", vbl_cmd_farm, "submit a render to Slurm as an array job of pass ranges plus a merge job"},
    {"options", vbl_cmd_options, "list the render options (scene keys, flags, ranges, defaults; --markdown)"},
};

static void vbl_cli_print_help(FILE* out)
{
    fprintf(out,
            "vbl %s - render OpenVDB volumes with virtual ray and beam lights\n\n"
            "usage: vbl <command> [options]\n       vbl --version | --help\n\ncommands:\n",
            vbl_version_string());
    for (size_t i = 0; i < sizeof vbl_cli_commands / sizeof vbl_cli_commands[0]; ++i)
        fprintf(out, "  %-14s %s\n", vbl_cli_commands[i].name, vbl_cli_commands[i].summary);
    fprintf(out, "\n'vbl <command> --help' describes a command's options.\n"
                 "Every command takes --memory-limit SIZE (e.g. 8G, 512M, 50%%; default VBL_MEMORY_LIMIT or 3/4 of\n"
                 "the physical memory): inputs and films needing more are refused (exit 3) before allocating.\n");
}

int vbl_cli_exit_code(vbl_result result)
{
    switch (result) {
    case VBL_SUCCESS: return VBL_EXIT_OK;
    case VBL_ERROR_INVALID_ARGUMENT: return VBL_EXIT_USAGE;
    case VBL_ERROR_FILE_IO: return VBL_EXIT_IO;
    case VBL_ERROR_INTERRUPTED: return VBL_EXIT_INTERRUPTED;
    case VBL_ERROR_FILE_NOT_FOUND:
    case VBL_ERROR_CORRUPT_FILE:
    case VBL_ERROR_UNSUPPORTED:
    case VBL_ERROR_GRID_NOT_FOUND:
    case VBL_ERROR_GRID_TYPE:
    case VBL_ERROR_BAD_VOXELS:
    case VBL_ERROR_SCENE: return VBL_EXIT_BAD_INPUT;
    default: return VBL_EXIT_FAILURE;
    }
}

int vbl_cli_fail(vbl_result result)
{
    const char* message = vbl_last_error_message();
    fprintf(stderr, "vbl: %s\n", message && message[0] ? message : vbl_result_name(result));
    return vbl_cli_exit_code(result);
}

/* --memory-limit SIZE / --memory-limit=SIZE anywhere before a "--" (every command), taken out of argv;
 * a malformed VBL_MEMORY_LIMIT is a usage error too. Returns -1 when fine, else the exit code. */
static int vbl_cli_take_memory_limit(int* argc, char** argv)
{
    const char* env = getenv("VBL_MEMORY_LIMIT");
    uint64_t bytes = 0;
    if (env && env[0] && vbl_parse_memory_size(env, &bytes) != VBL_SUCCESS) {
        fprintf(stderr, "vbl: VBL_MEMORY_LIMIT: %s\n", vbl_last_error_message());
        return VBL_EXIT_USAGE;
    }
    int out = 1;
    for (int a = 1; a < *argc; ++a) {
        if (!strcmp(argv[a], "--")) {
            while (a < *argc) argv[out++] = argv[a++];
            break;
        }
        const char* value = NULL;
        if (!strcmp(argv[a], "--memory-limit")) {
            if (a + 1 >= *argc) {
                fprintf(stderr, "vbl: --memory-limit needs a size (e.g. 8G, 512M, 50%%)\n");
                return VBL_EXIT_USAGE;
            }
            value = argv[++a];
        } else if (!strncmp(argv[a], "--memory-limit=", 15)) {
            value = argv[a] + 15;
        } else {
            argv[out++] = argv[a];
            continue;
        }
        if (vbl_parse_memory_size(value, &bytes) != VBL_SUCCESS || vbl_set_memory_limit(bytes) != VBL_SUCCESS) {
            fprintf(stderr, "vbl: --memory-limit: %s\n", vbl_last_error_message());
            return VBL_EXIT_USAGE;
        }
    }
    argv[out] = NULL;
    *argc = out;
    return -1;
}

int main(int argc, char** argv)
{
    const int limit_code = vbl_cli_take_memory_limit(&argc, argv);
    if (limit_code >= 0) return limit_code;
    if (argc < 2) {
        vbl_cli_print_help(stderr);
        return VBL_EXIT_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        vbl_cli_print_help(stdout);
        return VBL_EXIT_OK;
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "-V")) {
        printf("vbl %s\n", vbl_version_string());
        return VBL_EXIT_OK;
    }
    for (size_t i = 0; i < sizeof vbl_cli_commands / sizeof vbl_cli_commands[0]; ++i) {
        if (strcmp(argv[1], vbl_cli_commands[i].name)) continue;
        if (!strcmp(argv[1], "render")) return vbl_cli_commands[i].run(argc - 1, argv + 1); /* parses --flag=value itself */
        /* getopt_long's --flag=value for the other commands: split into --flag value */
        char** args = malloc(sizeof *args * (size_t)(2 * argc + 1));
        char** owned = malloc(sizeof *owned * (size_t)(argc + 1));
        if (!args || !owned) {
            free(args);
            free(owned);
            fprintf(stderr, "vbl: out of memory\n");
            return VBL_EXIT_FAILURE;
        }
        int n = 0, owned_count = 0, literal = 0;
        for (int a = 1; a < argc; ++a) {
            char* eq = !literal && argv[a][0] == '-' && argv[a][1] == '-' ? strchr(argv[a], '=') : NULL;
            if (!strcmp(argv[a], "--")) literal = 1;
            if (!eq) {
                args[n++] = argv[a];
                continue;
            }
            char* flag = malloc((size_t)(eq - argv[a]) + 1);
            if (!flag) {
                args[n++] = argv[a];
                continue;
            }
            memcpy(flag, argv[a], (size_t)(eq - argv[a]));
            flag[eq - argv[a]] = 0;
            owned[owned_count++] = flag;
            args[n++] = flag;
            args[n++] = eq + 1;
        }
        args[n] = NULL;
        int code = vbl_cli_commands[i].run(n, args);
        for (int k = 0; k < owned_count; ++k) free(owned[k]);
        free(owned);
        free(args);
        return code;
    }
    fprintf(stderr, "vbl: unknown command '%s' (see 'vbl --help')\n", argv[1]);
    return VBL_EXIT_USAGE;
}
