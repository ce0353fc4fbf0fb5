/* Split rendering end to end (issue 7): `vbl render --pass-range` parts merged with `vbl merge`
 * equal a single render of all the passes within float rounding, on every layer; `vbl merge`
 * refuses overlapping, gapped and incompatible inputs naming the file; `--resume` continues a
 * stopped render (time limit, SIGKILL after a checkpoint) to the image of an uninterrupted one
 * and refuses an incompatible checkpoint without touching it. Small images, fixed seeds. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "pipeline_test_util.h"

#define W PT_W
#define H PT_H

static void run_ok(const char* args)
{
    pt_run_expect(args, 0, NULL);
}

/* Every channel of `a` against the reference `b`: the same channel set; relative error below
 * `tolerance` where |b| > 1e-6 (absolute error below 1e-6 * tolerance elsewhere); samples equal;
 * variance and Z (combined by documented approximations) finite and non-negative. The transport
 * layers of `a` sum to its beauty exactly. Returns the largest relative error seen. */
static double compare_images(const char* path_a, const char* path_b, double tolerance)
{
    vbl_exr_image* a = pt_read_exr(path_a);
    vbl_exr_image* b = pt_read_exr(path_b);
    assert_int_equal(vbl_exr_image_width(a), vbl_exr_image_width(b));
    assert_int_equal(vbl_exr_image_height(a), vbl_exr_image_height(b));
    assert_int_equal(vbl_exr_image_channel_count(a), vbl_exr_image_channel_count(b));
    double worst = 0.0;
    for (int c = 0; c < vbl_exr_image_channel_count(a); ++c) {
        const char* name = vbl_exr_image_channel_name(a, c);
        int j = vbl_exr_image_find_channel(b, name);
        if (j < 0) fail_msg("%s has channel %s, %s does not", path_a, name, path_b);
        const float* x = vbl_exr_image_channel_pixels(a, c);
        const float* y = vbl_exr_image_channel_pixels(b, j);
        int approximate = !strcmp(name, "Z") || !strncmp(name, "variance.", 9);
        for (int i = 0; i < W * H; ++i) {
            assert_true(isfinite(x[i]));
            if (approximate) {
                assert_true(x[i] >= 0.0f);
                continue;
            }
            if (!strncmp(name, "samples.", 8)) {
                assert_true(x[i] == y[i]);
                continue;
            }
            double err = fabs((double)x[i] - (double)y[i]);
            double rel = fabs(y[i]) > 1e-6 ? err / fabs(y[i]) : err / 1e-6;
            if (rel > worst) worst = rel;
            if (rel > tolerance)
                fail_msg("%s vs %s: channel %s pixel %d: %.9g vs %.9g (relative error %.3g)", path_a, path_b, name, i,
                         x[i], y[i], rel);
        }
    }
    static const char* const rgb[3] = {"R", "G", "B"};
    static const char* const layers[3] = {"background", "volume_direct", "volume_from_volume"};
    for (int k = 0; k < 3; ++k) {
        const float* beauty = vbl_exr_image_channel_pixels(a, vbl_exr_image_find_channel(a, rgb[k]));
        const float* t[3];
        for (int l = 0; l < 3; ++l) {
            char name[64];
            snprintf(name, sizeof name, "%s.%s", layers[l], rgb[k]);
            t[l] = vbl_exr_image_channel_pixels(a, vbl_exr_image_find_channel(a, name));
            assert_non_null(t[l]);
        }
        for (int i = 0; i < W * H; ++i) assert_true(t[0][i] + t[1][i] + t[2][i] == beauty[i]);
    }
    vbl_exr_image_release(a);
    vbl_exr_image_release(b);
    return worst;
}

static void split_and_merge(const char* method_args)
{
    char args[8192];
    const char* single = ct_path(pt_dir, "single.exr");
    const char* p0 = ct_path(pt_dir, "p0.exr");
    const char* p1 = ct_path(pt_dir, "p1.exr");
    const char* merged = ct_path(pt_dir, "merged.exr");
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 8 --aov all %s", pt_scene, single, method_args);
    run_ok(args);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 8 --pass-range 0-3 --aov all %s", pt_scene, p0,
             method_args);
    run_ok(args);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --pass-range 4-7 --aov all %s", pt_scene, p1, method_args);
    run_ok(args);
    vbl_exr_image* part = pt_read_exr(p1);
    assert_string_equal(pt_attr(part, "vbl:first_pass"), "4");
    assert_string_equal(pt_attr(part, "vbl:passes"), "4");
    assert_string_equal(pt_attr(part, "vbl:pass_range"), "4-7");
    vbl_exr_image_release(part);
    snprintf(args, sizeof args, "merge -q '%s' '%s' '%s'", merged, p1, p0); /* any order */
    run_ok(args);
    vbl_exr_image* m = pt_read_exr(merged);
    assert_string_equal(pt_attr(m, "vbl:passes"), "8");
    assert_string_equal(pt_attr(m, "vbl:first_pass"), "0");
    assert_string_equal(pt_attr(m, "vbl:status"), "complete");
    vbl_exr_image_release(m);
    double worst = compare_images(merged, single, 1e-5);
    print_message("merge %s: max relative error %.3g against the single render\n", method_args, worst);
    remove(single), remove(p0), remove(p1), remove(merged);
}

static void test_merge_equals_single_render_pt(void** state)
{
    (void)state;
    split_and_merge("--method pt");
}

static void test_merge_equals_single_render_vbl(void** state)
{
    (void)state;
    split_and_merge("--method vbl --light-paths 8");
}

static void test_merge_refusals(void** state)
{
    (void)state;
    char args[8192], out[2048];
    snprintf(out, sizeof out, "%s", ct_path(pt_dir, "out.exr")); /* ct_path's buffers rotate */
    static const char* const parts[][2] = {{"a.exr", "--pass-range 0-3"},
                                           {"b.exr", "--pass-range 2-5"},
                                           {"c.exr", "--pass-range 6-7"},
                                           {"d.exr", "--pass-range 4-5 --seed 9"},
                                           {"e.exr", "--pass-range 4-5 --aov samples"},
                                           {"f.exr", "--pass-range 4-5 --method vpl"}};
    for (size_t i = 0; i < sizeof parts / sizeof parts[0]; ++i) {
        snprintf(args, sizeof args, "render '%s' -o '%s' -q %s", pt_scene, ct_path(pt_dir, parts[i][0]), parts[i][1]);
        run_ok(args);
    }
#define P(i) ct_path(pt_dir, parts[i][0])
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), P(1));
    pt_run_expect(args, 3, "overlaps");
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), P(2));
    pt_run_expect(args, 3, "passes 4-5 are missing");
    snprintf(args, sizeof args, "merge '%s' '%s'", out, P(2));
    pt_run_expect(args, 3, "passes 0-5 are missing");
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), P(3));
    pt_run_expect(args, 3, "vbl:seed");
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), P(4));
    pt_run_expect(args, 3, "samples.Y");
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), P(5));
    pt_run_expect(args, 3, "vbl:method");
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), ct_path(pt_dir, "missing.exr"));
    pt_run_expect(args, 3, "missing.exr");
    snprintf(args, sizeof args, "merge '%s'", out);
    pt_run_expect(args, 2, "no input");
    assert_true(access(out, F_OK) != 0); /* nothing written by a refused merge */
    /* a different scene (other resolution: other scene hash) */
    char other[2048];
    snprintf(other, sizeof other, "%s/other.json", pt_dir);
    ct_write_scene(other, W + 1, H, NULL);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --pass-range 4-5", other, ct_path(pt_dir, "g.exr"));
    run_ok(args);
    snprintf(args, sizeof args, "merge '%s' '%s' '%s'", out, P(0), ct_path(pt_dir, "g.exr"));
    pt_run_expect(args, 3, "g.exr");
    assert_true(access(out, F_OK) != 0);
    /* --allow-gaps: merges, marked partial */
    snprintf(args, sizeof args, "merge -q --allow-gaps '%s' '%s' '%s'", out, P(0), P(2));
    run_ok(args);
    vbl_exr_image* m = pt_read_exr(out);
    assert_string_equal(pt_attr(m, "vbl:status"), "partial");
    assert_string_equal(pt_attr(m, "vbl:passes"), "6");
    vbl_exr_image_release(m);
    /* unwritable output: exit 4 */
    snprintf(args, sizeof args, "merge '%s/no/such/dir/out.exr' '%s'", pt_dir, P(0));
    pt_run_expect(args, 4, "out.exr");
    for (size_t i = 0; i < sizeof parts / sizeof parts[0]; ++i) remove(P(i));
#undef P
    remove(ct_path(pt_dir, "g.exr"));
    remove(other);
    remove(out);
}

/* A render stopped by --time-limit after its first pass (--min-passes 1), resumed, equals the plain render. */
static void test_resume_after_time_limit(void** state)
{
    (void)state;
    char args[8192];
    const char* plain = ct_path(pt_dir, "plain.exr");
    const char* out = ct_path(pt_dir, "resumed.exr");
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 6 --spp 16 --aov all", pt_scene, plain);
    run_ok(args);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 6 --spp 16 --aov all --time-limit 0.000001 --min-passes 1", pt_scene,
             out);
    run_ok(args);
    vbl_exr_image* cp = pt_read_exr(out);
    assert_string_equal(pt_attr(cp, "vbl:status"), "time_limit");
    assert_string_equal(pt_attr(cp, "vbl:passes"), "1");
    vbl_exr_image_release(cp);
    /* an incompatible resume (other seed) fails and leaves the checkpoint as it was */
    uint64_t before = ct_fnv1a64_file(out);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 6 --spp 16 --aov all --seed 11 --resume", pt_scene, out);
    pt_run_expect(args, 3, "vbl:seed");
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 6 --spp 16 --resume", pt_scene, out);
    pt_run_expect(args, 3, "samples.Y");
    assert_true(ct_fnv1a64_file(out) == before);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 6 --spp 16 --aov all --resume", pt_scene, out);
    run_ok(args);
    vbl_exr_image* done = pt_read_exr(out);
    assert_string_equal(pt_attr(done, "vbl:status"), "complete");
    assert_string_equal(pt_attr(done, "vbl:passes"), "6");
    assert_string_equal(pt_attr(done, "vbl:first_pass"), "0");
    vbl_exr_image_release(done);
    double worst = compare_images(out, plain, 1e-5);
    print_message("resume after time limit: max relative error %.3g\n", worst);
    /* resuming a complete render does nothing */
    before = ct_fnv1a64_file(out);
    run_ok(args);
    assert_true(ct_fnv1a64_file(out) == before);
    remove(plain), remove(out);
}

/* SIGKILL (the checkpoint stays) or SIGTERM (the passes done are written, exit 5) after the first
 * checkpoint, then --resume: the same image as an uninterrupted render. */
static void test_resume_after_kill(void** state)
{
    (void)state;
    const char* plain = ct_path(pt_dir, "plain40.exr");
    char args[8192];
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 40 --spp 32 --threads 1", pt_scene, plain);
    run_ok(args);
    static const int signals[2] = {SIGKILL, SIGTERM};
    for (int k = 0; k < 2; ++k) {
        const char* out = ct_path(pt_dir, "killed.exr");
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) {
            execl(ct_vbl(), "vbl", "render", pt_scene, "-o", out, "-q", "--checkpoint-passes", "1", "--passes", "40",
                  "--spp", "32", "--threads", "1", (char*)NULL);
            _exit(127);
        }
        for (int waited = 0; access(out, F_OK) != 0; ++waited) {
            int status = 0;
            if (waitpid(pid, &status, WNOHANG) == pid) fail_msg("vbl render exited before a checkpoint (%d)", status);
            if (waited > 60000) {
                kill(pid, SIGKILL);
                waitpid(pid, NULL, 0);
                fail_msg("no checkpoint after 60 s");
            }
            pt_sleep_ms(1);
        }
        kill(pid, signals[k]);
        int status = 0;
        waitpid(pid, &status, 0);
        if (signals[k] == SIGTERM) assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 5);
        vbl_exr_image* cp = pt_read_exr(out);
        int done = atoi(pt_attr(cp, "vbl:passes"));
        print_message("%s after %d passes (%s)\n", k ? "SIGTERM" : "SIGKILL", done, pt_attr(cp, "vbl:status"));
        assert_true(done >= 1);
        vbl_exr_image_release(cp);
        snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 40 --spp 32 --threads 1 --resume", pt_scene, out);
        run_ok(args);
        double worst = compare_images(out, plain, 1e-5);
        print_message("resume after %s: max relative error %.3g\n", k ? "SIGTERM" : "SIGKILL", worst);
        remove(out);
    }
    remove(plain);
}

/* --resume with a pass range resumes within the range; with no file it renders from the start. */
static void test_resume_pass_range(void** state)
{
    (void)state;
    char args[8192];
    const char* ref = ct_path(pt_dir, "range_ref.exr");
    const char* out = ct_path(pt_dir, "range.exr");
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --pass-range 3-7", pt_scene, ref);
    run_ok(args);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --pass-range 3-7 --time-limit 0.000001 --min-passes 1", pt_scene, out);
    run_ok(args);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --pass-range 4-7 --resume", pt_scene, out);
    pt_run_expect(args, 3, "first_pass");
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --pass-range 3-7 --resume", pt_scene, out);
    run_ok(args);
    compare_images(out, ref, 1e-5);
    remove(out);
    run_ok(args); /* no file: a plain render */
    compare_images(out, ref, 0.0);
    remove(out), remove(ref);
}

/* `vbl farm submit --dry-run` writes the job scripts and prints the two sbatch commands; running
 * the array task script for every task id and then the merge script by hand (what Slurm does)
 * gives the single render. The real scheduler: test_farm_slurm.sh. */
static void test_farm_scripts_without_slurm(void** state)
{
    (void)state;
    char args[8192], out[2048], work[2048], single[2048];
    snprintf(out, sizeof out, "%s/farm.exr", pt_dir);
    snprintf(work, sizeof work, "%s/farm.exr.farm", pt_dir);
    snprintf(single, sizeof single, "%s/farm_single.exr", pt_dir);
    snprintf(args, sizeof args, "farm submit '%s' -o '%s' --passes 4 --chunks 3 --partition p1 --dry-run -- --threads 1",
             pt_scene, out);
    char* log = NULL;
    assert_int_equal(ct_vbl_run(args, &log, 0), 0);
    assert_non_null(log);
    if (!strstr(log, "'--array=0-2'") || !strstr(log, "'--dependency=afterok:<array_job>'") ||
        !strstr(log, "'--partition=p1'") || !strstr(log, "render.sh") || !strstr(log, "merge.sh"))
        fail_msg("dry run printed:\n%s", log);
    free(log);
    for (int task = 0; task < 3; ++task) {
        snprintf(args, sizeof args, "SLURM_ARRAY_TASK_ID=%d sh '%s/render.sh' >/dev/null 2>&1", task, work);
        assert_int_equal(system(args), 0);
    }
    snprintf(args, sizeof args, "sh '%s/merge.sh' >/dev/null 2>&1", work);
    assert_int_equal(system(args), 0);
    snprintf(args, sizeof args, "render '%s' -o '%s' -q --passes 4 --threads 1", pt_scene, single);
    run_ok(args);
    compare_images(out, single, 1e-5);
    /* usage errors */
    snprintf(args, sizeof args, "farm submit '%s' -o '%s' --passes 2 --chunks 3 --dry-run", pt_scene, out);
    pt_run_expect(args, 2, "--chunks 3");
    snprintf(args, sizeof args, "farm submit '%s' -o '%s' --passes 2 --chunks 1 --dry-run -- --pass-range 0-1", pt_scene,
             out);
    pt_run_expect(args, 2, "--pass-range");
    snprintf(args, sizeof args, "farm submit '%s/nope.json' -o '%s' --passes 2 --chunks 1 --dry-run", pt_dir, out);
    pt_run_expect(args, 3, "nope.json");
    ct_remove_dir(work);
    remove(out), remove(single);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_merge_equals_single_render_pt),
        cmocka_unit_test(test_merge_equals_single_render_vbl),
        cmocka_unit_test(test_merge_refusals),
        cmocka_unit_test(test_resume_after_time_limit),
        cmocka_unit_test(test_resume_after_kill),
        cmocka_unit_test(test_resume_pass_range),
        cmocka_unit_test(test_farm_scripts_without_slurm),
    };
    return cmocka_run_group_tests(tests, pt_setup, pt_teardown);
}
