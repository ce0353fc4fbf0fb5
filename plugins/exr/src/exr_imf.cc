// DWAA through OpenEXR's C++ library: OpenEXRCore 3.1 (Debian 12) implements every other codec
// but not DWAA/DWAB, for writing or reading. Same file layout as the Core path in exr_write.c.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "exr_internal.h"

namespace {

// Writes through vbl_exr_output_pwrite so the temporary-file/rename logic and the test hook apply.
class OutputStream : public Imf::OStream {
public:
    OutputStream(vbl_exr_output_file* file, const char* path) : Imf::OStream(path), file_(file) {}
    void write(const char c[], int n) override
    {
        if (n <= 0) return;
        if (vbl_exr_output_pwrite(file_, c, (uint64_t)n, position_) < 0)
            throw std::runtime_error(std::strerror(file_->failed_errno ? file_->failed_errno : EIO));
        position_ += (uint64_t)n;
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t pos) override { position_ = pos; }

private:
    vbl_exr_output_file* file_;
    uint64_t position_ = 0;
};

}  // namespace

extern "C" vbl_result vbl_exr_write_imf(vbl_exr_output_file* file, const char* path, int width, int height,
                                        const vbl_exr_plane* planes, int plane_count,
                                        const vbl_exr_write_options* opt, int tile_size)
{
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::DWAA_COMPRESSION;
        if (opt->dwa_quality > 0.0f) header.dwaCompressionLevel() = opt->dwa_quality;
        for (int i = 0; i < plane_count; ++i)
            header.channels().insert(planes[i].name, Imf::Channel(planes[i].half ? Imf::HALF : Imf::FLOAT, 1, 1, false));
        if (opt->chromaticities) {
            const float* c = opt->chromaticities;
            Imf::addChromaticities(header, Imf::Chromaticities(Imath::V2f(c[0], c[1]), Imath::V2f(c[2], c[3]),
                                                               Imath::V2f(c[4], c[5]), Imath::V2f(c[6], c[7])));
        }
        if (opt->color_space && opt->color_space[0])
            header.insert("oiio:ColorSpace", Imf::StringAttribute(opt->color_space));
        for (int i = 0; i < opt->attribute_count; ++i) {
            const vbl_exr_attribute& a = opt->attributes[i];
            switch (a.type) {
            case VBL_EXR_ATTRIBUTE_INT: header.insert(a.name, Imf::IntAttribute(a.int_value)); break;
            case VBL_EXR_ATTRIBUTE_DOUBLE: header.insert(a.name, Imf::DoubleAttribute(a.double_value)); break;
            case VBL_EXR_ATTRIBUTE_FLOAT: header.insert(a.name, Imf::FloatAttribute((float)a.double_value)); break;
            default: header.insert(a.name, Imf::StringAttribute(a.value ? a.value : "")); break;
            }
        }
        Imf::FrameBuffer frame;
        for (int i = 0; i < plane_count; ++i) {
            size_t bpe = planes[i].half ? 2 : 4;
            frame.insert(planes[i].name, Imf::Slice(planes[i].half ? Imf::HALF : Imf::FLOAT,
                                                    (char*)planes[i].data, bpe, bpe * (size_t)width));
        }
        OutputStream stream(file, path);
        if (opt->tiled) {
            header.setTileDescription(Imf::TileDescription((unsigned)tile_size, (unsigned)tile_size, Imf::ONE_LEVEL));
            Imf::TiledOutputFile out(stream, header, 1);
            out.setFrameBuffer(frame);
            out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
        } else {
            Imf::OutputFile out(stream, header, 1);
            out.setFrameBuffer(frame);
            out.writePixels(height);
        }
    } catch (const std::exception& e) {
        if (file->failed_errno)
            return vbl_report_error(VBL_ERROR_FILE_IO, "%s: write failed while writing pixels: %s", path,
                                    std::strerror(file->failed_errno));
        return vbl_report_error(VBL_ERROR_FILE_IO, "%s: OpenEXR failed: %s", path, e.what());
    }
    return VBL_SUCCESS;
}

extern "C" int vbl_exr_read_imf(const char* path, int plane_count, const char* const* names, float* const* planes,
                                int width, char* message, size_t message_size)
{
    try {
        Imf::InputFile in(path, 1);
        const Imath::Box2i dw = in.header().dataWindow();
        Imf::FrameBuffer frame;
        for (int i = 0; i < plane_count; ++i) {
            // Slices are addressed from pixel (0,0); shift the base by the data window origin.
            char* base = (char*)(planes[i] - (ptrdiff_t)dw.min.x - (ptrdiff_t)dw.min.y * (ptrdiff_t)width);
            frame.insert(names[i], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * (size_t)width));
        }
        in.setFrameBuffer(frame);
        in.readPixels(dw.min.y, dw.max.y);
    } catch (const std::exception& e) {
        std::snprintf(message, message_size, "%s", e.what());
        return -1;
    }
    return 0;
}
