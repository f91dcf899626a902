#pragma once
// Decoding untrusted PNG and JPEG bytes to RGBA8 through libpng and
// libjpeg-turbo, the maintained reference decoders: every malformed input is
// an error message, never a read past the data. Both check the header's size
// against `max_edge` before allocating, and the JPEG decoder refuses files
// of more than 500 progressive scans (each scan re-walks the whole image).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace cr {

struct DecodedImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, rows top to bottom
  int file_channels = 4;      // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA (palettes: 3, or 4 with transparency)
};

// Palette, grey and 16-bit PNGs are expanded to RGBA8 (16-bit channels
// rounded: (v * 255 + 32767) / 65535); no gamma is applied. False with
// `error` set (e.g. "PNG data is truncated") on failure.
bool decode_png(const uint8_t* bytes, size_t size, int max_edge, DecodedImage& out, std::string& error);

// Greyscale, YCbCr, RGB, CMYK and YCCK JPEGs to RGBA8 (alpha 255), decoded
// with the accurate integer IDCT and fancy upsampling.
bool decode_jpeg(const uint8_t* bytes, size_t size, int max_edge, DecodedImage& out, std::string& error);

}  // namespace cr
