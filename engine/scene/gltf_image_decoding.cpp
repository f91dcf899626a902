#include "engine/scene/gltf_image_decoding.h"

#include <algorithm>

#include "engine/output/image_decoding.h"

namespace cr {

namespace {

uint32_t read_be32(const unsigned char* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}
uint32_t read_be16(const unsigned char* p) { return (uint32_t(p[0]) << 8) | uint32_t(p[1]); }

// Width and height from a PNG's IHDR or a JPEG's SOF segment; false when the
// bytes are neither format or the header is cut short.
bool header_dimensions(const unsigned char* b, size_t size, uint32_t& w, uint32_t& h, std::string& why) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 8 && std::equal(kPng, kPng + 8, b)) {
    if (size < 24 || read_be32(b + 12) != 0x49484452u) {  // "IHDR"
      why = "PNG header is truncated or has no IHDR chunk";
      return false;
    }
    w = read_be32(b + 16);
    h = read_be32(b + 20);
    return true;
  }
  if (size >= 2 && b[0] == 0xFF && b[1] == 0xD8) {
    size_t i = 2;
    while (i + 4 <= size) {
      if (b[i] != 0xFF) break;
      unsigned char marker = b[i + 1];
      if (marker == 0xFF) {  // fill byte
        ++i;
        continue;
      }
      if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no payload
        i += 2;
        continue;
      }
      uint32_t len = read_be16(b + i + 2);
      bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
      if (sof) {
        if (i + 9 > size || len < 7) break;
        h = read_be16(b + i + 5);
        w = read_be16(b + i + 7);
        return true;
      }
      if (len < 2) break;
      i += 2 + len;
    }
    why = "JPEG data has no readable frame header";
    return false;
  }
  why = "not a PNG or JPEG image (the only formats glTF 2.0 allows)";
  return false;
}

}  // namespace

bool capture_gltf_image(tinygltf::Image* image, int image_index, std::string* err, std::string* warn,
                        int req_width, int req_height, const unsigned char* bytes, int size, void* user) {
  (void)err;
  (void)warn;
  (void)req_width;
  (void)req_height;
  ImageDecodeLog& log = *static_cast<ImageDecodeLog*>(user);
  uint32_t w = 0, h = 0;
  std::string why;
  if (size <= 0 || !header_dimensions(bytes, static_cast<size_t>(size), w, h, why)) {
    log.failures[image_index] = why.empty() ? "empty image data" : why;
    return true;
  }
  if (w == 0 || h == 0 || w > uint32_t(kMaxImageEdge) || h > uint32_t(kMaxImageEdge)) {
    log.failures[image_index] = "size " + std::to_string(w) + "x" + std::to_string(h) +
                                " is outside 1.." + std::to_string(kMaxImageEdge) + " per edge";
    return true;
  }
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  image->width = static_cast<int>(w);
  image->height = static_cast<int>(h);
  return true;
}

bool decode_gltf_image(const tinygltf::Image& image, int image_index, MipLevel& out, std::string& error) {
  (void)image_index;
  const bool png = image.image[0] == 0x89;  // capture let only PNG and JPEG through
  DecodedImage decoded;
  std::string why;
  const bool ok = png ? decode_png(image.image.data(), image.image.size(), kMaxImageEdge, decoded, why)
                      : decode_jpeg(image.image.data(), image.image.size(), kMaxImageEdge, decoded, why);
  // The header was read at capture, so it is the data that fails, or a size
  // unlike the header's (memory was estimated from the header).
  if (!ok || decoded.width != image.width || decoded.height != image.height) {
    error = std::string("truncated or corrupt ") + (png ? "PNG" : "JPEG") + " data (its header gives " +
            std::to_string(image.width) + "x" + std::to_string(image.height) + ", but the data does not decode" +
            (ok ? " to that size)" : ": " + why + ")");
    return false;
  }
  out.width = decoded.width;
  out.height = decoded.height;
  out.rgba = std::move(decoded.rgba);
  return true;
}

}  // namespace cr
