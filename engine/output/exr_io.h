#pragma once
// OpenEXR files: linear colour as half floats, depth and AOVs as floats.
#include <string>
#include <vector>

#include "engine/output/image.h"

namespace cr {

enum class ExrPixelType { Half, Float };

// One named channel of width * height values (row-major, top row first).
struct ExrChannel {
  std::string name;
  ExrPixelType type = ExrPixelType::Float;
  std::vector<float> values;
};

// A render's EXR output. Only `color` is required.
struct ExrImage {
  ImageRGBf color;                 // linear radiance -> R, G, B (HALF)
  std::vector<float> depth;        // distance in metres -> Z (FLOAT); +inf = sky; empty = none
  std::vector<ExrChannel> aovs;    // extra channels (FLOAT unless stated); names must not be R/G/B/Z
};

// Writes any set of channels atomically (ZIP compression, lossless).
// Throws cr::Error naming the file on a size mismatch, duplicate or empty
// channel name, or an OpenEXR error.
void write_exr_channels(const std::string& path, int width, int height,
                        const std::vector<ExrChannel>& channels);

// Writes R,G,B as HALF, Z as FLOAT (when depth is set) and the AOVs.
void write_exr(const std::string& path, const ExrImage& image);

// Reads R, G, B (required), Z (optional) and every other channel as an AOV
// (values converted to float, reported as Float). Throws cr::InputError naming
// the file when it is unreadable, not an EXR, or lacks R, G or B.
ExrImage read_exr(const std::string& path);

}  // namespace cr
