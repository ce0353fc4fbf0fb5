/* `vbl transmittance`: orthographic transmittance image of a volume looking along an axis through
 * its world bounding box, written as an 8-bit greyscale PNG (255 = fully transparent). */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fdopen */
#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

/* OpenMP when the CLI is compiled with it (pragmas vanish otherwise, without warnings). */
#ifdef _OPENMP
#define VBL_OMP(x) _Pragma(x)
#else
#define VBL_OMP(x)
#endif

static void vbl_tr_usage(FILE* out)
{
    fprintf(out,
            "usage: vbl transmittance FILE.vdb -o OUT.png [options]\n\n"
            "Renders the transmittance of a volume seen along an axis (orthographic, through the\n"
            "world bounding box) and prints the mean transmittance.\n\n"
            "options:\n"
            "  -o, --output OUT.png      output image (8-bit greyscale, white = transparent)\n"
            "  --grid NAME               float grid to read (default: density, or the only float grid)\n"
            "  --density-scale S         sigma_t = S * value, per world unit (default 1)\n"
            "  --estimator NAME          delta|ratio|residual|march|cached-delta|cached-ratio (default ratio)\n"
            "  --spp N                   estimates per pixel (default 16)\n"
            "  --resolution WxH          image size (default 256 wide, height from the aspect ratio)\n"
            "  --axis x|y|z              viewing axis, looking towards +axis (default z)\n"
            "  --seed N                  random seed (default 0)\n"
            "  -h, --help                this help\n");
}

/* libpng's default handlers print to stderr ("libpng error: Write Error" on a full disk): keep its
 * message for ours instead (one line naming the file). */
static void vbl_tr_png_error(png_structp png, png_const_charp message)
{
    char* saved = png_get_error_ptr(png);
    if (saved) snprintf(saved, 256, "%s", message ? message : "libpng error");
    png_longjmp(png, 1);
}

static void vbl_tr_png_warning(png_structp png, png_const_charp message)
{
    (void)png;
    (void)message;
}

static int vbl_tr_write_png(const char* path, const unsigned char* pixels, int w, int h)
{
    char png_message[256] = "";
    size_t len = strlen(path);
    char* tmp = malloc(len + 16);
    if (!tmp) return VBL_EXIT_IO;
    snprintf(tmp, len + 16, "%s.tmpXXXXXX", path);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        fprintf(stderr, "vbl: cannot write %s: %s\n", path, strerror(errno));
        free(tmp);
        return VBL_EXIT_IO;
    }
    FILE* f = fdopen(fd, "wb");
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, png_message, vbl_tr_png_error, vbl_tr_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int ok = f && png && info;
    if (ok && setjmp(png_jmpbuf(png))) ok = 0;
    else if (ok) {
        png_init_io(png, f);
        png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_write_info(png, info);
        for (int y = 0; y < h; ++y) png_write_row(png, (png_const_bytep)(pixels + (size_t)y * (size_t)w));
        png_write_end(png, NULL);
    }
    if (png) png_destroy_write_struct(&png, info ? &info : NULL);
    if (f) {
        if (fclose(f) != 0) ok = 0;
    } else close(fd);
    if (ok && rename(tmp, path) != 0) ok = 0;
    if (!ok) {
        fprintf(stderr, "vbl: cannot write %s: %s\n", path,
                errno ? strerror(errno) : (png_message[0] ? png_message : strerror(EIO)));
        remove(tmp);
    }
    free(tmp);
    return ok ? VBL_EXIT_OK : VBL_EXIT_IO;
}

static int vbl_tr_parse_int(const char* s, long lo, long hi, long* out)
{
    char* end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

int vbl_cmd_transmittance(int argc, char** argv)
{
    const char *input = NULL, *output = NULL, *grid = NULL;
    double scale = 1.0;
    long spp = 16, width = 0, height = 0, seed = 0;
    int axis = 2;
    vbl_transmittance_estimator estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* next = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            vbl_tr_usage(stdout);
            return VBL_EXIT_OK;
        }
        int takes = !strcmp(a, "-o") || !strcmp(a, "--output") || !strcmp(a, "--grid") || !strcmp(a, "--density-scale") ||
                    !strcmp(a, "--estimator") || !strcmp(a, "--spp") || !strcmp(a, "--resolution") || !strcmp(a, "--axis") ||
                    !strcmp(a, "--seed");
        if (takes && !next) {
            fprintf(stderr, "vbl transmittance: %s needs a value\n", a);
            return VBL_EXIT_USAGE;
        }
        if (!strcmp(a, "-o") || !strcmp(a, "--output")) output = next;
        else if (!strcmp(a, "--grid")) grid = next;
        else if (!strcmp(a, "--density-scale")) {
            char* end;
            scale = strtod(next, &end);
            if (end == next || *end || !(scale >= 0.0) || !isfinite(scale)) {
                fprintf(stderr, "vbl transmittance: --density-scale '%s' must be a finite number >= 0\n", next);
                return VBL_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--estimator")) {
            if (vbl_transmittance_estimator_parse(next, &estimator) != VBL_SUCCESS) {
                fprintf(stderr, "vbl transmittance: %s\n", vbl_last_error_message());
                return VBL_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--spp")) {
            if (!vbl_tr_parse_int(next, 1, 1 << 24, &spp)) {
                fprintf(stderr, "vbl transmittance: --spp '%s' must be an integer in [1, 16777216]\n", next);
                return VBL_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--seed")) {
            if (!vbl_tr_parse_int(next, 0, 2147483647L, &seed)) {
                fprintf(stderr, "vbl transmittance: --seed '%s' must be a non-negative integer\n", next);
                return VBL_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--resolution")) {
            char* x = strchr(next, 'x');
            char wbuf[32];
            if (!x || x == next || (size_t)(x - next) >= sizeof wbuf) {
                fprintf(stderr, "vbl transmittance: --resolution '%s' must be WxH\n", next);
                return VBL_EXIT_USAGE;
            }
            memcpy(wbuf, next, (size_t)(x - next));
            wbuf[x - next] = 0;
            if (!vbl_tr_parse_int(wbuf, 1, 16384, &width) || !vbl_tr_parse_int(x + 1, 1, 16384, &height)) {
                fprintf(stderr, "vbl transmittance: --resolution '%s' must be WxH with 1..16384 each\n", next);
                return VBL_EXIT_USAGE;
            }
        } else if (!strcmp(a, "--axis")) {
            if (!strcmp(next, "x")) axis = 0;
            else if (!strcmp(next, "y")) axis = 1;
            else if (!strcmp(next, "z")) axis = 2;
            else {
                fprintf(stderr, "vbl transmittance: --axis '%s' must be x, y or z\n", next);
                return VBL_EXIT_USAGE;
            }
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vbl transmittance: unknown option '%s' (see --help)\n", a);
            return VBL_EXIT_USAGE;
        } else if (!input) {
            input = a;
            continue;
        } else {
            fprintf(stderr, "vbl transmittance: unexpected argument '%s'\n", a);
            return VBL_EXIT_USAGE;
        }
        ++i; /* consumed the value */
    }
    if (!input || !output) {
        fprintf(stderr, "vbl transmittance: %s\n", !input ? "missing input FILE.vdb" : "missing -o OUT.png");
        vbl_tr_usage(stderr);
        return VBL_EXIT_USAGE;
    }

    vbl_volume_load_options lopt = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    lopt.grid_name = grid;
    vbl_volume* volume = NULL;
    vbl_result r = vbl_volume_load(input, &lopt, &volume);
    if (r != VBL_SUCCESS) return vbl_cli_fail(r);
    vbl_volume_info info;
    memset(&info, 0, sizeof info);
    info.size = sizeof info;
    r = vbl_volume_get_info(volume, &info);
    if (r != VBL_SUCCESS) {
        vbl_volume_release(volume);
        return vbl_cli_fail(r);
    }
    /* Image plane axes: (u, v) = the two other axes in cyclic order (x: y,z; y: z,x; z: x,y). */
    const int au = (axis + 1) % 3, av = (axis + 2) % 3;
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = info.world_bbox_min[a];
        hi[a] = info.world_bbox_max[a];
        if (!(hi[a] >= lo[a])) lo[a] = hi[a] = 0.0; /* empty grid */
    }
    double eu = hi[au] - lo[au], ev = hi[av] - lo[av], depth = hi[axis] - lo[axis];
    if (width == 0) {
        width = 256;
        height = eu > 0.0 && ev > 0.0 ? (long)fmax(1.0, fmin(16384.0, floor(256.0 * ev / eu + 0.5))) : 256;
    }
    unsigned char* pixels = malloc((size_t)width * (size_t)height);
    double* values = malloc(sizeof(double) * (size_t)width * (size_t)height);
    if (!pixels || !values) {
        free(pixels);
        free(values);
        vbl_volume_release(volume);
        fprintf(stderr, "vbl transmittance: out of memory for a %ldx%ld image\n", width, height);
        return VBL_EXIT_FAILURE;
    }
    int failed = 0;
    const double margin = 1e-6 * (depth + 1.0);
    VBL_OMP("omp parallel for schedule(dynamic, 1)")
    for (long y = 0; y < height; ++y) {
        for (long x = 0; x < width; ++x) {
            double o[3], d[3] = {0.0, 0.0, 0.0};
            o[au] = lo[au] + eu * ((double)x + 0.5) / (double)width;
            o[av] = hi[av] - ev * ((double)y + 0.5) / (double)height; /* row 0 at the top */
            o[axis] = lo[axis] - margin;
            d[axis] = 1.0;
            vbl_transmittance_options opt = VBL_TRANSMITTANCE_OPTIONS_DEFAULT;
            opt.estimator = estimator;
            opt.density_scale = scale;
            opt.seed = (uint64_t)seed * 0x9E3779B97F4A7C15ull + (uint64_t)(y * width + x);
            vbl_transmittance_result res;
            size_t index = (size_t)y * (size_t)width + (size_t)x;
            if (vbl_volume_transmittance(volume, o, d, 0.0, depth + 2.0 * margin, &opt, (unsigned)spp, &res) !=
                VBL_SUCCESS) {
                VBL_OMP("omp atomic write")
                failed = 1;
                values[index] = 0.0;
                continue;
            }
            double t = res.mean < 0.0 ? 0.0 : (res.mean > 1.0 ? 1.0 : res.mean);
            values[index] = res.mean;
            pixels[index] = (unsigned char)lround(255.0 * t);
        }
    }
    vbl_volume_release(volume);
    if (failed) {
        free(pixels);
        free(values);
        fprintf(stderr, "vbl transmittance: %s\n", vbl_last_error_message());
        return VBL_EXIT_FAILURE;
    }
    double sum = 0.0;
    for (size_t i = 0; i < (size_t)width * (size_t)height; ++i) sum += values[i];
    free(values);
    int rc = vbl_tr_write_png(output, pixels, (int)width, (int)height);
    free(pixels);
    if (rc != VBL_EXIT_OK) return rc;
    printf("mean transmittance %.6f (%s, %ld spp, %ldx%ld, axis %c) -> %s\n", sum / ((double)width * (double)height),
           vbl_transmittance_estimator_name(estimator), spp, width, height, "xyz"[axis], output);
    return VBL_EXIT_OK;
}
