#include "atmosphere/tools/lut_debug_output.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/core/luminance.h"
#include "engine/output/color_map.h"
#include "engine/output/exr_io.h"
#include "engine/output/png_io.h"

namespace cr {

namespace {

// A 2D view of a LUT (3D volumes: slices side by side).
struct Flat {
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;
};

Flat flatten(const LutImage& img) {
  Flat f;
  f.width = img.width * img.depth;
  f.height = img.height;
  f.texels.resize(size_t(f.width) * f.height);
  for (int z = 0; z < img.depth; ++z)
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) f.texels[size_t(y) * f.width + z * img.width + x] = img.at(x, y, z);
  return f;
}

void write_view(const Flat& f, const std::string& base, bool logarithmic, std::vector<std::string>& written) {
  std::vector<ExrChannel> channels(3);
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    channels[size_t(c)].name = names[c];
    channels[size_t(c)].type = ExrPixelType::Float;
    channels[size_t(c)].values.resize(f.texels.size());
    for (size_t i = 0; i < f.texels.size(); ++i) channels[size_t(c)].values[i] = f.texels[i][c];
  }
  write_exr_channels(base + ".exr", f.width, f.height, channels);
  written.push_back(base + ".exr");

  std::vector<float> values(f.texels.size());
  float peak = 0.0f;
  for (size_t i = 0; i < f.texels.size(); ++i) {
    values[i] = std::isfinite(luminance(f.texels[i])) ? std::max(luminance(f.texels[i]), 0.0f) : 0.0f;
    peak = std::max(peak, values[i]);
  }
  for (float& v : values) {
    if (logarithmic) {
      v = peak > 0.0f && v > 0.0f ? std::clamp((std::log10(v / peak) + 4.0f) / 4.0f, 0.0f, 1.0f) : 0.0f;
    } else {
      v = std::clamp(v, 0.0f, 1.0f);
    }
  }
  write_png(base + ".png", heatmap_rgb8(values, f.width, f.height, 1.0f));
  written.push_back(base + ".png");
}

}  // namespace

std::vector<std::string> write_lut_debug_views(const LutScheduler& luts, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> written;
  if (auto t = luts.transmittance()) write_view(flatten(t->image()), dir + "/transmittance", false, written);
  if (auto ms = luts.multiscattering()) write_view(flatten(ms->image()), dir + "/multiscattering", true, written);
  if (auto sv = luts.skyview()) {
    write_view(flatten(sv->image()), dir + "/skyview", true, written);
    write_view(flatten(sv->mie_image()), dir + "/skyview_mie_unphased", true, written);
  }
  if (auto ap = luts.aerial_perspective()) {
    write_view(flatten(ap->luminance()), dir + "/aerial_perspective_luminance", true, written);
    write_view(flatten(ap->transmittance()), dir + "/aerial_perspective_transmittance", false, written);
  }
  return written;
}

}  // namespace cr
