#pragma once
// PNG files (8 bits per channel): read through libpng (image_decoding.h),
// written through stb_image_write.
#include <string>

#include "engine/output/image.h"

namespace cr {

// Writes an 8-bit PNG (1..4 channels) atomically. Throws cr::Error.
void write_png(const std::string& path, const Image8& image);

// Quantises display-encoded values in [0,1] (already tonemapped and
// sRGB-encoded) to an RGB8 image; values outside [0,1] are clamped.
Image8 to_rgb8(const ImageRGBf& display);

// Reads a PNG. `channels` 0 keeps the file's channel count, 1..4 converts
// (3 drops alpha, expands grey). 16-bit files are reduced to 8 bits.
// Throws cr::InputError naming the file for anything that is not a valid PNG.
Image8 read_png(const std::string& path, int channels = 0);

// Reads a PNG as RGB display values in [0,1] (code / 255; alpha dropped).
ImageRGBf read_png_rgb(const std::string& path);

}  // namespace cr
