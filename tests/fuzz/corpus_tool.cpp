// Seed-corpus helper for make_corpus.sh (built without sanitizers):
//   cr_fuzz_corpus_tool inline IN.gltf OUT.gltf
// writes IN with every external buffer and image URI that names a readable
// file (relative to IN's folder, at most 8 MiB) replaced by a base64 data
// URI, so the seed is one self-contained input for the glTF target (which
// sees only its own bytes). A file that is not JSON is copied unchanged.
//   cr_fuzz_corpus_tool images OUT_DIR
// writes small PNG (grey, grey+alpha, RGB, RGBA) and baseline JPEG (grey,
// RGB) images of a few odd sizes: cheap seeds for every decoder path the
// image target reaches, where the project's own images are large.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace fs = std::filesystem;

namespace {

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

std::string percent_decode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit((unsigned char)s[i + 1]) && std::isxdigit((unsigned char)s[i + 2])) {
      out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

bool read_file(const fs::path& p, std::string& out) {
  std::error_code ec;
  if (!fs::is_regular_file(p, ec) || fs::file_size(p, ec) > (size_t(8) << 20)) return false;
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  out = s.str();
  return bool(in);
}

std::string mime_of(const std::string& bytes, bool image) {
  if (!image) return "application/octet-stream";
  if (bytes.size() >= 2 && (unsigned char)bytes[0] == 0xFF && (unsigned char)bytes[1] == 0xD8) return "image/jpeg";
  return "image/png";
}

int inline_uris(const fs::path& in, const fs::path& out) {
  std::string text;
  if (!read_file(in, text)) {
    std::cerr << in << ": cannot read\n";
    return 1;
  }
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  int inlined = 0;
  if (doc.is_object()) {
    for (const char* list : {"buffers", "images"}) {
      auto it = doc.find(list);
      if (it == doc.end() || !it->is_array()) continue;
      for (nlohmann::json& entry : *it) {
        if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) continue;
        const std::string uri = entry["uri"].get<std::string>();
        std::string bytes;
        if (uri.rfind("data:", 0) == 0 || !read_file(in.parent_path() / percent_decode(uri), bytes)) continue;
        entry["uri"] = "data:" + mime_of(bytes, list[0] == 'i') + ";base64," + base64(bytes);
        ++inlined;
      }
    }
  }
  std::ofstream o(out, std::ios::binary);
  o << (inlined > 0 ? doc.dump() : text);
  return o ? 0 : 1;
}

int small_images(const fs::path& dir) {
  struct Size { int w, h; };
  const Size sizes[] = {{1, 1}, {3, 2}, {16, 16}, {33, 7}};
  int written = 0;
  for (const Size& sz : sizes) {
    for (int comp = 1; comp <= 4; ++comp) {
      std::vector<unsigned char> px(size_t(sz.w) * sz.h * comp);
      for (size_t i = 0; i < px.size(); ++i) px[i] = (unsigned char)(i * 71u + (i / comp) * 13u);
      const std::string stem = std::to_string(sz.w) + "x" + std::to_string(sz.h) + "_c" + std::to_string(comp);
      written += stbi_write_png((dir / ("gen_" + stem + ".png")).c_str(), sz.w, sz.h, comp, px.data(), sz.w * comp) != 0;
      if (comp == 1 || comp == 3) {
        for (int q : {40, 95}) {
          const fs::path p = dir / ("gen_" + stem + "_q" + std::to_string(q) + ".jpg");
          written += stbi_write_jpg(p.c_str(), sz.w, sz.h, comp, px.data(), q) != 0;
        }
      }
    }
  }
  return written > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "inline") return inline_uris(argv[2], argv[3]);
  if (argc == 3 && std::string(argv[1]) == "images") return small_images(argv[2]);
  std::cerr << "usage: cr_fuzz_corpus_tool inline IN.gltf OUT.gltf | images OUT_DIR\n";
  return 2;
}
