#pragma once
// Writing float32 lookup tables as OpenEXR images (one EXR channel per table channel).
#include <span>
#include <string>

namespace hairlod::bcsdf {

// Writes a width x height float32 image with the named channels to `path` (ZIP compression);
// `values` holds height rows of width pixels of channels.size() interleaved floats. Throws
// hairlod::Error naming the path on failure.
void write_exr(const std::string& path, int width, int height, std::span<const std::string> channels,
               std::span<const float> values);

}  // namespace hairlod::bcsdf
