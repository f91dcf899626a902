#include "engine/output/png_io.h"

#include <climits>
#include <cstring>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/core/srgb.h"
#include "engine/output/image_decoding.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace cr {
namespace {

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::string*>(context);
  out->append(static_cast<const char*>(data), static_cast<size_t>(size));
}

// Golden and reference images: the engine renders at most 16384 per side.
constexpr int kMaxPngEdge = 16384;

}  // namespace

void write_png(const std::string& path, const Image8& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4)
    throw Error(path + ": cannot write PNG of " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + "x" + std::to_string(image.channels));
  const size_t row = static_cast<size_t>(image.width) * image.channels;
  if (image.data.size() != row * image.height)
    throw Error(path + ": PNG pixel data size does not match " + std::to_string(image.width) +
                "x" + std::to_string(image.height) + "x" + std::to_string(image.channels));
  if (row > static_cast<size_t>(INT_MAX)) throw Error(path + ": PNG row too large");
  std::string encoded;
  const int ok = stbi_write_png_to_func(append_bytes, &encoded, image.width, image.height,
                                        image.channels, image.data.data(), static_cast<int>(row));
  if (!ok) throw Error(path + ": PNG encoding failed");
  write_file_atomic(path, encoded);
}

Image8 to_rgb8(const ImageRGBf& display) {
  Image8 out;
  out.width = display.width;
  out.height = display.height;
  out.channels = 3;
  out.data.resize(display.rgb.size());
  for (size_t i = 0; i < display.rgb.size(); ++i) out.data[i] = quantize_unorm8(display.rgb[i]);
  return out;
}

Image8 read_png(const std::string& path, int channels) {
  if (channels < 0 || channels > 4) throw Error("read_png: channels must be 0..4");
  const std::string bytes = read_file_bytes(path);
  if (bytes.empty()) throw InputError(path, "empty file, not a PNG image");
  DecodedImage decoded;
  std::string error;
  if (!decode_png(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), kMaxPngEdge, decoded, error))
    throw InputError(path, "invalid PNG: " + error);
  Image8 image;
  image.width = decoded.width;
  image.height = decoded.height;
  image.channels = channels != 0 ? channels : decoded.file_channels;
  const size_t pixels = size_t(decoded.width) * size_t(decoded.height);
  image.data.resize(pixels * size_t(image.channels));
  for (size_t i = 0; i < pixels; ++i) {
    const uint8_t* p = &decoded.rgba[4 * i];
    uint8_t* q = &image.data[i * size_t(image.channels)];
    if (image.channels >= 3) {
      for (int c = 0; c < image.channels; ++c) q[c] = p[c];
    } else {
      q[0] = uint8_t((p[0] * 77u + p[1] * 150u + p[2] * 29u) >> 8);  // luma (grey files: the grey itself)
      if (image.channels == 2) q[1] = p[3];
    }
  }
  return image;
}

ImageRGBf read_png_rgb(const std::string& path) {
  const Image8 png = read_png(path, 3);
  ImageRGBf image(png.width, png.height);
  for (size_t i = 0; i < png.data.size(); ++i) image.rgb[i] = png.data[i] / 255.0f;
  return image;
}

}  // namespace cr
