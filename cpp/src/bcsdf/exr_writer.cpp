#include "hairlod/bcsdf/exr_writer.h"

#include <exception>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include "hairlod/core/error.h"

namespace hairlod::bcsdf {

void write_exr(const std::string& path, int width, int height, std::span<const std::string> channels,
               std::span<const float> values) {
    if (width < 1 || height < 1 || channels.empty())
        throw Error(path + ": an EXR table needs a positive size and at least one channel");
    const size_t stride = channels.size();
    if (values.size() != static_cast<size_t>(width) * height * stride)
        throw Error(path + ": table has " + std::to_string(values.size()) + " values, expected " +
                    std::to_string(static_cast<size_t>(width) * height * stride));
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (size_t c = 0; c < stride; ++c) {
            header.channels().insert(channels[c], Imf::Channel(Imf::FLOAT));
            // The slice reads through a char pointer; OpenEXR never writes through it.
            char* base = reinterpret_cast<char*>(const_cast<float*>(values.data() + c));
            frame.insert(channels[c], Imf::Slice(Imf::FLOAT, base, sizeof(float) * stride,
                                                 sizeof(float) * stride * static_cast<size_t>(width)));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    } catch (const std::exception& e) {
        throw Error(path + ": cannot write EXR: " + e.what());
    }
}

}  // namespace hairlod::bcsdf
