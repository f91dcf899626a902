#pragma once
// Builds small glTF files for tests: geometry goes into one buffer embedded as
// a base64 data URI, the document is written to the build tree.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cr::test {

// A 1x1 RGBA PNG (128, 128, 255, 255): a flat normal-map texel.
inline const char* kFlatNormalPng =
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGNoaPj/HwAGggL/s75RMwAAAABJRU5ErkJggg==";

inline std::string base64(const std::vector<uint8_t>& data) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = uint32_t(data[i]) << 16;
    if (i + 1 < data.size()) v |= uint32_t(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < data.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? k[v & 63] : '=';
  }
  return out;
}

// Directory for files written by tests.
inline std::string test_output_dir() {
  std::filesystem::path dir = std::filesystem::path(CR_BINARY_DIR) / "test_scene_files";
  std::filesystem::create_directories(dir);
  return dir.string();
}

class GltfBuilder {
 public:
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};

  // A float accessor of `type` ("VEC3", ...) holding `values`.
  int floats(const std::vector<float>& values, const char* type, size_t components) {
    int view = add_view(values.data(), values.size() * sizeof(float));
    return add_accessor(view, 5126, type, values.size() / components);
  }

  template <typename T>
  int indices(const std::vector<T>& values) {
    static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4);
    int component = sizeof(T) == 1 ? 5121 : sizeof(T) == 2 ? 5123 : 5125;
    int view = add_view(values.data(), values.size() * sizeof(T));
    return add_accessor(view, component, "SCALAR", values.size());
  }

  // A bufferView holding `values` as they are (sparse indices and values,
  // quantized or compressed data).
  template <typename T>
  int view(const std::vector<T>& values) {
    return add_view(values.data(), values.size() * sizeof(T));
  }

  int add(const char* array, nlohmann::json item) {
    doc[array].push_back(std::move(item));
    return static_cast<int>(doc[array].size()) - 1;
  }

  // Writes <test_output_dir>/<name> and returns its path.
  std::string write(const std::string& name) {
    nlohmann::json d = doc;
    if (!bin_.empty()) {
      d["buffers"] = nlohmann::json::array(
          {{{"byteLength", bin_.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin_)}}});
    }
    std::string path = test_output_dir() + "/" + name;
    std::ofstream(path) << d.dump(1);
    return path;
  }

 private:
  int add_view(const void* data, size_t bytes) {
    size_t offset = bin_.size();
    bin_.resize(offset + bytes);
    std::memcpy(bin_.data() + offset, data, bytes);
    while (bin_.size() % 4) bin_.push_back(0);
    return add("bufferViews", {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  }
  int add_accessor(int view, int component, const char* type, size_t count) {
    return add("accessors", {{"bufferView", view}, {"componentType", component}, {"type", type}, {"count", count}});
  }

  std::vector<uint8_t> bin_;
};

// Positions of an axis-aligned unit cube centred on the origin, four
// vertices per face (24), and its 36 indices, counter-clockwise from outside.
inline void unit_cube(std::vector<float>& positions, std::vector<uint32_t>& indices) {
  const int axes[6][3] = {{0, 1, 2}, {0, 1, 2}, {1, 2, 0}, {1, 2, 0}, {2, 0, 1}, {2, 0, 1}};
  for (int f = 0; f < 6; ++f) {
    float s = f % 2 == 0 ? 1.0f : -1.0f;
    int n = axes[f][2], u = axes[f][0], v = axes[f][1];
    uint32_t base = static_cast<uint32_t>(positions.size() / 3);
    const float corners[4][2] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
    for (const auto& c : corners) {
      float p[3];
      p[n] = 0.5f * s;
      p[u] = c[0];
      p[v] = c[1] * s;  // flip one tangent axis on the negative face to keep CCW from outside
      positions.insert(positions.end(), p, p + 3);
    }
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(base + i);
  }
}

}  // namespace cr::test
