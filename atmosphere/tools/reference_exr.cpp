#include "atmosphere/tools/reference_exr.h"

#include "engine/core/error.h"
#include "engine/output/exr_io.h"

namespace cr {

namespace {

// The reference's spectrum is recorded in the file as a channel "spectral":
// 1 at every pixel for the full-spectral reference, 0 for the RGB one.
const char* const kSpectrumChannel = "spectral";

const char* spectrum_name(bool spectral) { return spectral ? "spectral" : "rgb"; }

}  // namespace

void write_reference_exr(const std::string& path, const std::vector<glm::vec3>& px, const std::vector<float>& y,
                         const std::vector<float>& noise, const std::vector<glm::vec2>& ratio_noise, bool spectral,
                         int w, int h) {
  ExrImage img;
  img.color = ImageRGBf(w, h);
  for (size_t i = 0; i < px.size(); ++i)
    for (int c = 0; c < 3; ++c) img.color.rgb[i * 3 + size_t(c)] = px[i][c];
  img.aovs.push_back({"Y", ExrPixelType::Float, y});
  img.aovs.push_back({"noise", ExrPixelType::Float, noise});
  img.aovs.push_back({kSpectrumChannel, ExrPixelType::Float, std::vector<float>(px.size(), spectral ? 1.0f : 0.0f)});
  std::vector<float> rg(px.size()), bg(px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    rg[i] = ratio_noise[i].x;
    bg[i] = ratio_noise[i].y;
  }
  img.aovs.push_back({"rg_noise", ExrPixelType::Float, rg});
  img.aovs.push_back({"bg_noise", ExrPixelType::Float, bg});
  write_exr(path, img);
}

void read_reference_exr(const std::string& path, int w, int h, bool spectral, ReferenceLuminance& r) {
  std::vector<float>& y = r.luminance;
  std::vector<float>& noise = r.noise;
  const ExrImage img = read_exr(path);
  if (img.color.width != w || img.color.height != h)
    throw InputError(path, "size " + std::to_string(img.color.width) + "x" + std::to_string(img.color.height) +
                               " does not match --width/--height " + std::to_string(w) + "x" + std::to_string(h));
  y.clear();
  noise.clear();
  const std::vector<float>* spectrum = nullptr;
  const std::vector<float>*rg = nullptr, *bg = nullptr;
  for (const ExrChannel& c : img.aovs) {
    if (c.name == "Y") y = c.values;
    if (c.name == "noise") noise = c.values;
    if (c.name == kSpectrumChannel) spectrum = &c.values;
    if (c.name == "rg_noise") rg = &c.values;
    if (c.name == "bg_noise") bg = &c.values;
  }
  r.ratio_noise.clear();
  if (rg && bg && rg->size() == y.size() && bg->size() == y.size())  // optional: older references lack them
    for (size_t i = 0; i < y.size(); ++i) r.ratio_noise.insert(r.ratio_noise.end(), {(*rg)[i], (*bg)[i]});
  if (y.empty() || noise.empty()) throw InputError(path, "channels Y and noise: missing (not written by sky-accuracy --out)");
  if (spectrum == nullptr || spectrum->empty())
    throw InputError(path, "no \"spectral\" channel: written by an older sky-accuracy (RGB reference under a 110000 lx "
                           "white sun); render it again");
  const bool stored_spectral = spectrum->front() > 0.5f;
  if (stored_spectral != spectral)
    throw InputError(path, std::string("a ") + spectrum_name(stored_spectral) + " reference, but --spectrum is " +
                               spectrum_name(spectral) + ": pass --spectrum " + spectrum_name(stored_spectral) +
                               " or render it again");
  r.color = img.color.rgb;
}

}  // namespace cr
