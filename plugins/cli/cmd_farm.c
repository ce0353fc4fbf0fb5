/* `vbl farm submit SCENE.json -o OUT.exr --passes N --chunks K`: submits a render to Slurm as an
 * array job of K pass ranges (each task `vbl render --pass-range A-B --resume`) plus a merge job
 * (`vbl merge`) that runs after every task succeeded (docs/readme/pipeline.md, "Render farms").
 * The job scripts are written into a work folder (default OUT.exr.farm/) and submitted with
 * sbatch ($VBL_SBATCH, else `sbatch` in PATH); the job ids are printed on stdout. */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"

#define VBL_FARM_MAX_ARGS 64

static void vbl_farm_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl farm submit SCENE.json -o OUT.exr --passes N --chunks K [options] [-- RENDER-OPTIONS...]\n\n"
            "Splits a render of N passes into K pass ranges and submits them to Slurm as one array job (task i\n"
            "runs 'vbl render SCENE --pass-range A-B --resume' into WORK/part-i.exr), plus a merge job\n"
            "(--dependency=afterok on the array) running 'vbl merge OUT.exr WORK/part-*.exr'. The result equals\n"
            "a single-machine render of N passes within float rounding. Scene, VDBs, output and vbl must be\n"
            "on a filesystem every node sees, at the same paths.\n\n"
            "  -o, --output OUT.exr   the merged EXR\n"
            "  --passes N             passes of the whole render (N >= 1)\n"
            "  --chunks K             array tasks (1 <= K <= N); task i renders passes i*N/K .. (i+1)*N/K-1\n"
            "  --partition P          Slurm partition for both jobs\n"
            "  --sbatch-arg ARG       extra sbatch option for both jobs (repeatable), e.g. --sbatch-arg=--time=2:00:00\n"
            "  --job-name NAME        Slurm job name (default vbl-<OUT name>)\n"
            "  --work-dir DIR         job scripts, logs and partial EXRs (default OUT.exr.farm)\n"
            "  --vbl PATH             the vbl binary the nodes run (default: this one)\n"
            "  --dry-run              write the job scripts and print the sbatch commands, submit nothing\n"
            "  -- RENDER-OPTIONS      passed to every 'vbl render' (e.g. --method vrl --aov all)\n\n"
            "Prints 'array_job ID' and 'merge_job ID' on stdout. Exit codes: 0 submitted, 1 sbatch failed,\n"
            "2 bad command line, 3 scene not found, 4 cannot write the work folder.\n");
}

/* Appends `s` single-quoted for sh to out. */
static void vbl_farm_quote(FILE* out, const char* s)
{
    fputc('\'', out);
    for (; *s; ++s) {
        if (*s == '\'') fputs("'\\''", out);
        else fputc(*s, out);
    }
    fputc('\'', out);
}

/* Absolute path of a file that may not exist yet: realpath of its folder + its name. */
static int vbl_farm_absolute(const char* path, char* out, size_t size)
{
    const char* slash = strrchr(path, '/');
    char dir[PATH_MAX];
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == path) snprintf(dir, sizeof dir, "/");
    else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    char* real = realpath(dir, NULL);
    if (!real) return 0;
    int n = snprintf(out, size, "%s/%s", strcmp(real, "/") ? real : "", slash ? slash + 1 : path);
    free(real);
    return n > 0 && (size_t)n < size && (slash ? slash[1] != 0 : 1);
}

/* Runs argv, capturing stdout (sbatch --parsable prints "JOBID[;CLUSTER]"). Returns the job id or
 * -1 (stderr of the child passes through). */
static long vbl_farm_sbatch(char* const* argv)
{
    int fds[2];
    if (pipe(fds)) return -1;
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        dup2(fds[1], STDOUT_FILENO);
        close(fds[0]);
        close(fds[1]);
        execvp(argv[0], argv);
        fprintf(stderr, "vbl farm: cannot run %s (%s)\n", argv[0], strerror(errno));
        _exit(127);
    }
    close(fds[1]);
    char text[256];
    size_t n = 0;
    ssize_t got;
    while (n + 1 < sizeof text && (got = read(fds[0], text + n, sizeof text - 1 - n)) > 0) n += (size_t)got;
    text[n] = 0;
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return -1;
    char* end = NULL;
    long id = strtol(text, &end, 10);
    return end != text && id > 0 ? id : -1;
}

static void vbl_farm_print_command(char* const* argv)
{
    for (int i = 0; argv[i]; ++i) {
        if (i) fputc(' ', stdout);
        vbl_farm_quote(stdout, argv[i]);
    }
    fputc('\n', stdout);
}

static int vbl_farm_submit(int argc, char** argv)
{
    const char *scene = NULL, *output = NULL, *partition = NULL, *job_name = NULL, *work = NULL, *vbl = NULL;
    const char* sbatch_args[VBL_FARM_MAX_ARGS];
    const char* render_args[VBL_FARM_MAX_ARGS];
    int sbatch_count = 0, render_count = 0, dry_run = 0;
    long passes = 0, chunks = 0;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            vbl_farm_usage(stdout);
            return VBL_EXIT_OK;
        }
        if (!strcmp(a, "--")) {
            for (++i; i < argc; ++i) {
                if (render_count >= VBL_FARM_MAX_ARGS) {
                    fprintf(stderr, "vbl farm: more than %d render options\n", VBL_FARM_MAX_ARGS);
                    return VBL_EXIT_USAGE;
                }
                render_args[render_count++] = argv[i];
            }
            break;
        }
        if (!strcmp(a, "--dry-run")) {
            dry_run = 1;
            continue;
        }
        if (!strncmp(a, "--sbatch-arg=", 13)) {
            if (sbatch_count >= VBL_FARM_MAX_ARGS) return VBL_EXIT_USAGE;
            sbatch_args[sbatch_count++] = a + 13;
            continue;
        }
        if (a[0] != '-') {
            if (scene) {
                fprintf(stderr, "vbl farm: more than one scene file ('%s', '%s')\n", scene, a);
                return VBL_EXIT_USAGE;
            }
            scene = a;
            continue;
        }
        if (!v) {
            fprintf(stderr, "vbl farm: %s needs a value (see 'vbl farm --help')\n", a);
            return VBL_EXIT_USAGE;
        }
        char* end = NULL;
        if (!strcmp(a, "-o") || !strcmp(a, "--output")) output = v;
        else if (!strcmp(a, "--partition")) partition = v;
        else if (!strcmp(a, "--job-name")) job_name = v;
        else if (!strcmp(a, "--work-dir")) work = v;
        else if (!strcmp(a, "--vbl")) vbl = v;
        else if (!strcmp(a, "--sbatch-arg")) {
            if (sbatch_count >= VBL_FARM_MAX_ARGS) return VBL_EXIT_USAGE;
            sbatch_args[sbatch_count++] = v;
        } else if (!strcmp(a, "--passes") || !strcmp(a, "--chunks")) {
            long n = strtol(v, &end, 10);
            if (!end || *end || n < 1 || n > INT_MAX) {
                fprintf(stderr, "vbl farm: invalid value '%s' for %s\n", v, a);
                return VBL_EXIT_USAGE;
            }
            if (a[2] == 'p') passes = n;
            else chunks = n;
        } else {
            fprintf(stderr, "vbl farm: unknown option '%s' (see 'vbl farm --help')\n", a);
            return VBL_EXIT_USAGE;
        }
        ++i;
    }
    if (!scene || !output || passes < 1 || chunks < 1) {
        fprintf(stderr, "vbl farm submit: %s\n\n",
                !scene ? "no scene file given" : !output ? "no output given (-o OUT.exr)"
                                               : passes < 1 ? "--passes N is required" : "--chunks K is required");
        vbl_farm_usage(stderr);
        return VBL_EXIT_USAGE;
    }
    if (chunks > passes) {
        fprintf(stderr, "vbl farm: --chunks %ld is more than --passes %ld (every task needs a pass)\n", chunks, passes);
        return VBL_EXIT_USAGE;
    }
    for (int i = 0; i < render_count; ++i)
        if (!strcmp(render_args[i], "-o") || !strcmp(render_args[i], "--output") ||
            !strcmp(render_args[i], "--passes") || !strcmp(render_args[i], "--pass-range") ||
            !strcmp(render_args[i], "--frames")) {
            fprintf(stderr, "vbl farm: %s cannot be a render option here (the farm sets it)\n", render_args[i]);
            return VBL_EXIT_USAGE;
        }

    char scene_abs[PATH_MAX], out_abs[PATH_MAX], work_abs[PATH_MAX], vbl_abs[PATH_MAX];
    char* real_scene = realpath(scene, NULL);
    if (!real_scene) {
        fprintf(stderr, "vbl farm: %s: cannot find the scene file (%s)\n", scene, strerror(errno));
        return VBL_EXIT_BAD_INPUT;
    }
    snprintf(scene_abs, sizeof scene_abs, "%s", real_scene);
    free(real_scene);
    if (!vbl_farm_absolute(output, out_abs, sizeof out_abs)) {
        fprintf(stderr, "vbl farm: %s: the output folder does not exist\n", output);
        return VBL_EXIT_IO;
    }
    char work_default[PATH_MAX];
    snprintf(work_default, sizeof work_default, "%.*s.farm", (int)(sizeof work_default - 6), out_abs);
    if (!work) work = work_default;
    mkdir(work, 0777); /* may exist: resubmissions reuse it (tasks resume their parts) */
    char* real_work = realpath(work, NULL);
    struct stat st;
    if (!real_work || stat(real_work, &st) || !S_ISDIR(st.st_mode) || access(real_work, W_OK)) {
        fprintf(stderr, "vbl farm: %s: cannot create or write the work folder (%s)\n", work, strerror(errno));
        free(real_work);
        return VBL_EXIT_IO;
    }
    snprintf(work_abs, sizeof work_abs, "%s", real_work);
    free(real_work);
    char* real_vbl = realpath(vbl ? vbl : "/proc/self/exe", NULL);
    if (!real_vbl) {
        fprintf(stderr, "vbl farm: %s: cannot find the vbl binary\n", vbl ? vbl : "/proc/self/exe");
        return VBL_EXIT_USAGE;
    }
    snprintf(vbl_abs, sizeof vbl_abs, "%s", real_vbl);
    free(real_vbl);
    char name[256];
    if (job_name) snprintf(name, sizeof name, "%.200s", job_name);
    else {
        const char* base = strrchr(out_abs, '/');
        snprintf(name, sizeof name, "vbl-%.200s", base ? base + 1 : out_abs);
    }

    /* the array job script: task i -> pass range i */
    char render_sh[PATH_MAX + 16], merge_sh[PATH_MAX + 16];
    snprintf(render_sh, sizeof render_sh, "%s/render.sh", work_abs);
    snprintf(merge_sh, sizeof merge_sh, "%s/merge.sh", work_abs);
    FILE* f = fopen(render_sh, "w");
    if (!f) {
        fprintf(stderr, "vbl farm: %s: cannot write (%s)\n", render_sh, strerror(errno));
        return VBL_EXIT_IO;
    }
    fprintf(f, "#!/bin/sh\n# vbl farm: array task i renders pass range i of %ld passes into part-i.exr\n", passes);
    fprintf(f, "#SBATCH --output=%s/render-%%A_%%a.log\n", work_abs);
    fprintf(f, "set -eu\ncase \"${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}\" in\n");
    for (long i = 0; i < chunks; ++i)
        fprintf(f, "%ld) range=%ld-%ld ;;\n", i, i * passes / chunks, (i + 1) * passes / chunks - 1);
    fprintf(f, "*) echo \"vbl farm: no pass range for task $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\nesac\nexec ");
    vbl_farm_quote(f, vbl_abs);
    fprintf(f, " render ");
    vbl_farm_quote(f, scene_abs);
    fprintf(f, " -o ");
    vbl_farm_quote(f, work_abs);
    fprintf(f, "\"/part-$SLURM_ARRAY_TASK_ID.exr\" --passes %ld --pass-range \"$range\" --resume --progress lines",
            passes);
    for (int i = 0; i < render_count; ++i) {
        fputc(' ', f);
        vbl_farm_quote(f, render_args[i]);
    }
    fputc('\n', f);
    int bad = fclose(f) != 0;
    f = bad ? NULL : fopen(merge_sh, "w");
    if (!f) {
        fprintf(stderr, "vbl farm: %s: cannot write (%s)\n", bad ? render_sh : merge_sh, strerror(errno));
        return VBL_EXIT_IO;
    }
    fprintf(f, "#!/bin/sh\n# vbl farm: merges the %ld parts into the output\n", chunks);
    fprintf(f, "#SBATCH --output=%s/merge-%%j.log\nset -eu\nexec ", work_abs);
    vbl_farm_quote(f, vbl_abs);
    fprintf(f, " merge ");
    vbl_farm_quote(f, out_abs);
    for (long i = 0; i < chunks; ++i) {
        char part[PATH_MAX + 32];
        snprintf(part, sizeof part, "%s/part-%ld.exr", work_abs, i);
        fputc(' ', f);
        vbl_farm_quote(f, part);
    }
    fputc('\n', f);
    if (fclose(f) != 0) {
        fprintf(stderr, "vbl farm: %s: cannot write\n", merge_sh);
        return VBL_EXIT_IO;
    }
    chmod(render_sh, 0755);
    chmod(merge_sh, 0755);

    /* sbatch command lines */
    const char* sbatch = getenv("VBL_SBATCH");
    if (!sbatch || !sbatch[0]) sbatch = "sbatch";
    char array_opt[64], name_opt[300], merge_name_opt[320], partition_opt[300], dependency_opt[64];
    snprintf(array_opt, sizeof array_opt, "--array=0-%ld", chunks - 1);
    snprintf(name_opt, sizeof name_opt, "--job-name=%s", name);
    snprintf(merge_name_opt, sizeof merge_name_opt, "--job-name=%s-merge", name);
    if (partition) snprintf(partition_opt, sizeof partition_opt, "--partition=%s", partition);
    char* cmd[VBL_FARM_MAX_ARGS + 16];
    int k = 0;
    cmd[k++] = (char*)sbatch;
    cmd[k++] = "--parsable";
    cmd[k++] = name_opt;
    if (partition) cmd[k++] = partition_opt;
    for (int i = 0; i < sbatch_count; ++i) cmd[k++] = (char*)sbatch_args[i];
    int fixed = k;
    cmd[k++] = array_opt;
    cmd[k++] = render_sh;
    cmd[k] = NULL;
    if (dry_run) {
        vbl_farm_print_command(cmd);
        cmd[1 + 1] = merge_name_opt;
        cmd[fixed] = "--dependency=afterok:<array_job>";
        cmd[fixed + 1] = "--kill-on-invalid-dep=yes";
        cmd[fixed + 2] = merge_sh;
        cmd[fixed + 3] = NULL;
        vbl_farm_print_command(cmd);
        fprintf(stderr, "vbl farm: dry run: job scripts in %s, nothing submitted\n", work_abs);
        return VBL_EXIT_OK;
    }
    long array_job = vbl_farm_sbatch(cmd);
    if (array_job < 0) {
        fprintf(stderr, "vbl farm: sbatch failed for the render array job (%s)\n", render_sh);
        return VBL_EXIT_FAILURE;
    }
    snprintf(dependency_opt, sizeof dependency_opt, "--dependency=afterok:%ld", array_job);
    cmd[2] = merge_name_opt;
    cmd[fixed] = dependency_opt;
    cmd[fixed + 1] = "--kill-on-invalid-dep=yes";
    cmd[fixed + 2] = merge_sh;
    cmd[fixed + 3] = NULL;
    long merge_job = vbl_farm_sbatch(cmd);
    printf("array_job %ld\n", array_job);
    if (merge_job < 0) {
        fflush(stdout);
        fprintf(stderr, "vbl farm: sbatch failed for the merge job (%s); the array job %ld was submitted\n", merge_sh,
                array_job);
        return VBL_EXIT_FAILURE;
    }
    printf("merge_job %ld\n", merge_job);
    fflush(stdout);
    fprintf(stderr, "vbl farm: %ld passes in %ld tasks (array job %ld), merge job %ld -> %s\n", passes, chunks,
            array_job, merge_job, out_abs);
    return VBL_EXIT_OK;
}

int vbl_cmd_farm(int argc, char** argv)
{
    if (argc >= 2 && !strcmp(argv[1], "submit")) return vbl_farm_submit(argc - 1, argv + 1);
    if (argc >= 2 && (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help"))) {
        vbl_farm_usage(stdout);
        return VBL_EXIT_OK;
    }
    fprintf(stderr, "vbl farm: %s (usage: vbl farm submit SCENE.json -o OUT.exr --passes N --chunks K ...)\n",
            argc < 2 ? "no sub-command" : "unknown sub-command");
    return VBL_EXIT_USAGE;
}
