#pragma once
// Images of a glTF load, in two steps. While tinygltf parses, capture_gltf_image
// (its image callback) only checks the format and dimensions in the file header
// and keeps the encoded bytes; failures are recorded per image instead of
// aborting, so the loader can list every bad or missing image in one message
// before spending time decoding. Images whose file could not be read never
// reach the callback: they come back from tinygltf with a URI and no bytes.
// decode_gltf_image then decodes only the images materials actually use.
#include <map>
#include <string>

#include <tiny_gltf.h>

#include "engine/scene/scene.h"

namespace cr {

// Largest accepted image edge: 16384^2 RGBA8 is already 1 GiB before mips.
constexpr int kMaxImageEdge = 16384;

struct ImageDecodeLog {
  std::map<int, std::string> failures;  // glTF image index -> why it is unusable
};

// tinygltf::LoadImageDataFunction; `user` is an ImageDecodeLog. Accepts only
// PNG and JPEG (the formats glTF 2.0 allows) within kMaxImageEdge.
bool capture_gltf_image(tinygltf::Image* image, int image_index, std::string* err, std::string* warn,
                        int req_width, int req_height, const unsigned char* bytes, int size, void* user);

// Decodes a captured image to RGBA8 (16-bit channels rounded to 8 bits) with
// libpng or libjpeg-turbo (engine/output/image_decoding.h), at the size its
// header gives (so memory can be estimated from the header). Returns false
// with `error` set on failure.
bool decode_gltf_image(const tinygltf::Image& image, int image_index, MipLevel& out, std::string& error);

}  // namespace cr
