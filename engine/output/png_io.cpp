#include "engine/output/png_io.h"

#include <climits>
#include <cstring>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/core/srgb.h"

// Private copies of stb: libtinygltf.so also carries stb_image symbols, so
// these are made file-local (static) to avoid clashing definitions.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#include <stb/stb_image.h>  // via /usr/include: a system header, so its warnings stay quiet

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

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

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
  if (bytes.size() < sizeof(kPngSignature) ||
      std::memcmp(bytes.data(), kPngSignature, sizeof(kPngSignature)) != 0)
    throw InputError(path, "not a PNG file (bad signature)");
  if (bytes.size() > static_cast<size_t>(INT_MAX)) throw InputError(path, "PNG file too large");
  int width = 0, height = 0, file_channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                          static_cast<int>(bytes.size()), &width, &height,
                                          &file_channels, channels);
  if (!pixels) throw InputError(path, std::string("invalid PNG: ") + stbi_failure_reason());
  Image8 image;
  image.width = width;
  image.height = height;
  image.channels = channels != 0 ? channels : file_channels;
  const size_t size = static_cast<size_t>(width) * height * image.channels;
  image.data.assign(pixels, pixels + size);
  stbi_image_free(pixels);
  return image;
}

ImageRGBf read_png_rgb(const std::string& path) {
  const Image8 png = read_png(path, 3);
  ImageRGBf image(png.width, png.height);
  for (size_t i = 0; i < png.data.size(); ++i) image.rgb[i] = png.data[i] / 255.0f;
  return image;
}

}  // namespace cr
