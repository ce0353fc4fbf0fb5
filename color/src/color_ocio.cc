// OpenColorIO adapter behind vbl_color.h: configs, conversions, display/view, chromaticities.
#include <OpenColorIO/OpenColorIO.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "color_internal.h"
#include "vbl_color.h"

namespace OCIO = OCIO_NAMESPACE;

struct vbl_color_config {
    std::atomic<int> refcount{1};
    OCIO::ConstConfigRcPtr config;
    std::string source;
};

namespace {

std::string space_list(const OCIO::ConstConfigRcPtr& config)
{
    std::string list;
    for (int i = 0; i < config->getNumColorSpaces(); ++i) {
        if (i) list += ", ";
        list += "'";
        list += config->getColorSpaceNameByIndex(i);
        list += "'";
    }
    return list;
}

vbl_result open_builtin(vbl_color_config* cfg)
{
    std::istringstream stream(vbl_color_builtin_config_text());
    cfg->config = OCIO::Config::CreateFromStream(stream);
    cfg->source = "<libvbl built-in>";
    return VBL_SUCCESS;
}

vbl_result check_channels(int channels)
{
    if (channels != 3 && channels != 4)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "colour conversion: %d channels per pixel (3 or 4 allowed)",
                                channels);
    return VBL_SUCCESS;
}

void apply(const OCIO::ConstProcessorRcPtr& processor, float* pixels, size_t count, int channels)
{
    OCIO::ConstCPUProcessorRcPtr cpu = processor->getDefaultCPUProcessor();
    // One row per call keeps the image-desc dimensions within `long` for any size.
    const size_t row = 1u << 16;
    for (size_t start = 0; start < count; start += row) {
        size_t n = count - start < row ? count - start : row;
        OCIO::PackedImageDesc desc(pixels + start * (size_t)channels, (long)n, 1, channels);
        cpu->apply(desc);
    }
}

// ---- chromaticity maths (CIE xy -> matrices), Bradford adaptation --------------------------
struct Primaries {
    const char* name;
    double xy[8];
};
const Primaries known_primaries[] = {
    {"Rec.709", {0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290}},
    {"ACES AP1", {0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767}},
    {"ACES AP0", {0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.0770, 0.32168, 0.33767}},
    {"Rec.2020", {0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290}},
    {"P3-D65", {0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.3127, 0.3290}},
};

struct M3 {
    double m[3][3];
};

M3 mul(const M3& a, const M3& b)
{
    M3 r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) r.m[i][j] += a.m[i][k] * b.m[k][j];
    return r;
}

void mulv(const M3& a, const double v[3], double out[3])
{
    for (int i = 0; i < 3; ++i) out[i] = a.m[i][0] * v[0] + a.m[i][1] * v[1] + a.m[i][2] * v[2];
}

M3 inverse(const M3& a)
{
    const double(*m)[3] = a.m;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    M3 r;
    r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
    r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
    r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
    r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
    r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
    r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
    r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
    return r;
}

void xy_to_xyz(double x, double y, double out[3])
{
    out[0] = x / y;
    out[1] = 1.0;
    out[2] = (1.0 - x - y) / y;
}

M3 rgb_to_xyz(const double* xy)
{
    M3 p;
    for (int c = 0; c < 3; ++c) {
        double v[3];
        xy_to_xyz(xy[2 * c], xy[2 * c + 1], v);
        for (int i = 0; i < 3; ++i) p.m[i][c] = v[i];
    }
    double w[3], s[3];
    xy_to_xyz(xy[6], xy[7], w);
    mulv(inverse(p), w, s);
    for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) p.m[i][c] *= s[c];
    return p;
}

M3 bradford(const double* src_white, const double* dst_white)
{
    const M3 b = {{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
    double sw[3], dw[3], s[3], d[3];
    xy_to_xyz(src_white[0], src_white[1], sw);
    xy_to_xyz(dst_white[0], dst_white[1], dw);
    mulv(b, sw, s);
    mulv(b, dw, d);
    M3 scale = {{{d[0] / s[0], 0, 0}, {0, d[1] / s[1], 0}, {0, 0, d[2] / s[2]}}};
    return mul(inverse(b), mul(scale, b));
}

// Linear RGB with primaries `p` -> ACES2065-1 (AP0), adapting the white by Bradford.
M3 to_ap0(const double* p)
{
    const double* ap0 = known_primaries[2].xy;
    return mul(inverse(rgb_to_xyz(ap0)), mul(bradford(p + 6, ap0 + 6), rgb_to_xyz(p)));
}

}  // namespace

extern "C" {

vbl_result vbl_color_config_open(const char* path, vbl_color_config** out_config)
{
    if (!out_config) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_color_config_open: NULL output");
    *out_config = nullptr;
    vbl_color_config* cfg = new (std::nothrow) vbl_color_config;
    if (!cfg) return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "out of memory for a colour config");
    const char* from_env = nullptr;
    if (!path) {
        const char* env = std::getenv("OCIO");
        if (env && env[0]) path = from_env = env;
    }
    try {
        if (!path || !path[0] || !std::strcmp(path, "libvbl")) {
            open_builtin(cfg);
        } else {
            FILE* probe = std::fopen(path, "rb");
            if (!probe) {
                delete cfg;
                return vbl_report_error(VBL_ERROR_FILE_NOT_FOUND, "%s%s: cannot open the OpenColorIO config",
                                        from_env ? "$OCIO=" : "", path);
            }
            std::fclose(probe);
            cfg->config = OCIO::Config::CreateFromFile(path);
            cfg->source = path;
        }
        cfg->config->validate();
    } catch (const std::exception& e) {
        std::string where = cfg->source.empty() ? std::string(path ? path : "") : cfg->source;
        delete cfg;
        return vbl_report_error(VBL_ERROR_CORRUPT_FILE, "%s%s: invalid OpenColorIO config: %s",
                                from_env ? "$OCIO=" : "", where.c_str(), e.what());
    }
    *out_config = cfg;
    return VBL_SUCCESS;
}

void vbl_color_config_retain(vbl_color_config* config)
{
    if (config) config->refcount.fetch_add(1);
}

void vbl_color_config_release(vbl_color_config* config)
{
    if (config && config->refcount.fetch_sub(1) == 1) delete config;
}

const char* vbl_color_config_source(const vbl_color_config* config) { return config ? config->source.c_str() : ""; }

const char* vbl_color_shipped_config_path(void) { return VBL_COLOR_INSTALLED_CONFIG; }

vbl_result vbl_color_resolve_space(const vbl_color_config* config, const char* name, const char** out_name)
{
    if (out_name) *out_name = nullptr;
    if (!config || !name || !name[0])
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "colour space name is empty");
    OCIO::ConstColorSpaceRcPtr cs = config->config->getColorSpace(name);
    if (!cs)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "unknown colour space '%s' in OpenColorIO config %s (known: %s)",
                                name, config->source.c_str(), space_list(config->config).c_str());
    // The name's storage belongs to the config's colour space, which lives as long as the config.
    if (out_name) *out_name = config->config->getColorSpaceNameByIndex(config->config->getIndexForColorSpace(cs->getName()));
    return VBL_SUCCESS;
}

int vbl_color_space_count(const vbl_color_config* config) { return config ? config->config->getNumColorSpaces() : 0; }

const char* vbl_color_space_name(const vbl_color_config* config, int index)
{
    if (!config || index < 0 || index >= config->config->getNumColorSpaces()) return nullptr;
    return config->config->getColorSpaceNameByIndex(index);
}

const char* vbl_color_default_display(const vbl_color_config* config)
{
    return config ? config->config->getDefaultDisplay() : nullptr;
}

const char* vbl_color_default_view(const vbl_color_config* config, const char* display)
{
    if (!config) return nullptr;
    if (!display) display = config->config->getDefaultDisplay();
    return config->config->getDefaultView(display);
}

vbl_result vbl_color_convert(const vbl_color_config* config, const char* src, const char* dst, float* pixels,
                             size_t pixel_count, int channels)
{
    const char* s = nullptr;
    const char* d = nullptr;
    vbl_result r = check_channels(channels);
    if (r == VBL_SUCCESS) r = vbl_color_resolve_space(config, src, &s);
    if (r == VBL_SUCCESS) r = vbl_color_resolve_space(config, dst, &d);
    if (r != VBL_SUCCESS) return r;
    if (!std::strcmp(s, d) || pixel_count == 0) return VBL_SUCCESS;
    if (!pixels) return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "colour conversion: NULL pixels");
    try {
        apply(config->config->getProcessor(s, d), pixels, pixel_count, channels);
    } catch (const std::exception& e) {
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "cannot convert '%s' to '%s': %s", s, d, e.what());
    }
    return VBL_SUCCESS;
}

vbl_result vbl_color_convert_rgb(const vbl_color_config* config, const char* src, const char* dst, float rgb[3])
{
    return vbl_color_convert(config, src, dst, rgb, 1, 3);
}

vbl_result vbl_color_display_view(const vbl_color_config* config, const char* src, const char* display,
                                  const char* view, float exposure_stops, float* pixels, size_t pixel_count,
                                  int channels)
{
    const char* s = nullptr;
    vbl_result r = check_channels(channels);
    if (r == VBL_SUCCESS) r = vbl_color_resolve_space(config, src, &s);
    if (r != VBL_SUCCESS) return r;
    if (!std::isfinite(exposure_stops) || std::fabs(exposure_stops) > 64.0f)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "exposure %g is outside [-64, 64] stops", (double)exposure_stops);
    const OCIO::ConstConfigRcPtr& c = config->config;
    if (!display) display = c->getDefaultDisplay();
    bool found = false;
    std::string displays;
    for (int i = 0; i < c->getNumDisplays(); ++i) {
        if (!std::strcmp(c->getDisplay(i), display)) found = true;
        displays += std::string(i ? ", '" : "'") + c->getDisplay(i) + "'";
    }
    if (!found)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "unknown display '%s' in OpenColorIO config %s (known: %s)",
                                display, config->source.c_str(), displays.c_str());
    if (!view) view = c->getDefaultView(display);
    found = false;
    std::string views;
    for (int i = 0; i < c->getNumViews(display); ++i) {
        if (!std::strcmp(c->getView(display, i), view)) found = true;
        views += std::string(i ? ", '" : "'") + c->getView(display, i) + "'";
    }
    if (!found)
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "unknown view '%s' of display '%s' (known: %s)", view, display,
                                views.c_str());
    if (!pixels || pixel_count == 0) return VBL_SUCCESS;
    const float gain = std::exp2(exposure_stops);
    if (gain != 1.0f)
        for (size_t i = 0; i < pixel_count; ++i)
            for (int k = 0; k < 3; ++k) pixels[i * (size_t)channels + (size_t)k] *= gain;
    try {
        OCIO::DisplayViewTransformRcPtr t = OCIO::DisplayViewTransform::Create();
        t->setSrc(s);
        t->setDisplay(display);
        t->setView(view);
        apply(c->getProcessor(t), pixels, pixel_count, channels);
    } catch (const std::exception& e) {
        return vbl_report_error(VBL_ERROR_INVALID_ARGUMENT, "display '%s' view '%s' from '%s': %s", display, view, s, e.what());
    }
    return VBL_SUCCESS;
}

vbl_result vbl_color_space_chromaticities(const vbl_color_config* config, const char* space, float out[8])
{
    const char* s = nullptr;
    vbl_result r = vbl_color_resolve_space(config, space, &s);
    if (r != VBL_SUCCESS) return r;
    OCIO::ConstColorSpaceRcPtr interchange = config->config->getColorSpace("aces_interchange");
    if (!interchange)
        return vbl_report_error(VBL_ERROR_UNSUPPORTED, "%s: config has no aces_interchange role; chromaticities of '%s' unknown",
                                config->source.c_str(), s);
    // Columns of the space's matrix to AP0, plus a linearity probe (0.5, 0.25, 2).
    float probe[5 * 3] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5f, 0.25f, 2.0f, 0, 0, 0};
    try {
        apply(config->config->getProcessor(s, interchange->getName()), probe, 5, 3);
    } catch (const std::exception& e) {
        return vbl_report_error(VBL_ERROR_UNSUPPORTED, "chromaticities of '%s': %s", s, e.what());
    }
    for (int k = 0; k < 3; ++k) {
        double linear = 0.5 * probe[k] + 0.25 * probe[3 + k] + 2.0 * probe[6 + k];
        if (std::fabs(probe[9 + k] - linear) > 1e-4 * (1.0 + std::fabs(linear)) || std::fabs(probe[12 + k]) > 1e-6)
            return vbl_report_error(VBL_ERROR_UNSUPPORTED, "colour space '%s' is not linear: no chromaticities", s);
    }
    for (const Primaries& p : known_primaries) {
        M3 m = to_ap0(p.xy);
        double err = 0.0;
        for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) err = std::fmax(err, std::fabs(m.m[i][c] - probe[c * 3 + i]));
        if (err < 2e-3) {
            for (int i = 0; i < 8; ++i) out[i] = (float)p.xy[i];
            return VBL_SUCCESS;
        }
    }
    return vbl_report_error(VBL_ERROR_UNSUPPORTED,
                            "colour space '%s' has primaries other than Rec.709, AP1, AP0, Rec.2020 or P3-D65", s);
}

}  // extern "C"
