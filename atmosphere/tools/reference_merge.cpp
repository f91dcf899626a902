#include "atmosphere/tools/reference_merge.h"

#include <cmath>

#include "engine/core/error.h"

namespace cr {

ReferenceLuminance merge_references(const std::vector<ReferenceLuminance>& refs, const std::string& what) {
  if (refs.empty()) throw InputError(what, "no reference to merge");
  const size_t n = refs[0].luminance.size();
  std::vector<double> weight(refs.size());
  for (size_t k = 0; k < refs.size(); ++k) {
    const ReferenceLuminance& r = refs[k];
    if (r.luminance.size() != n || r.noise.size() != n || (!r.color.empty() && r.color.size() != 3 * n) ||
        (!r.ratio_noise.empty() && r.ratio_noise.size() != 2 * n))
      throw InputError(what, "references of different sizes cannot be merged");
    for (size_t j = 0; j < k; ++j)
      if (refs[j].luminance == r.luminance)
        throw InputError(what, "references " + std::to_string(j + 1) + " and " + std::to_string(k + 1) +
                                   " are the same image (same --seed): merging them would understate the noise");
    double mean_var = 0.0;
    for (float s : r.noise) mean_var += double(s) * s;
    mean_var /= double(n ? n : 1);
    // A noiseless reference (exact) outweighs any noisy one.
    weight[k] = mean_var > 0.0 ? 1.0 / mean_var : 1e300;
  }
  if (refs.size() == 1) return refs[0];
  double total = 0.0;
  for (double w : weight) total += w;
  ReferenceLuminance out;
  out.luminance.resize(n);
  out.noise.resize(n);
  bool colors = true;
  for (const ReferenceLuminance& r : refs) colors = colors && !r.color.empty();
  if (colors) out.color.resize(3 * n);
  bool ratios = true;
  for (const ReferenceLuminance& r : refs) ratios = ratios && !r.ratio_noise.empty();
  if (ratios) out.ratio_noise.resize(2 * n);
  for (size_t i = 0; i < n; ++i) {
    double y = 0.0, var = 0.0;
    for (size_t k = 0; k < refs.size(); ++k) {
      const double w = weight[k] / total;
      y += w * refs[k].luminance[i];
      var += w * w * double(refs[k].noise[i]) * refs[k].noise[i];
    }
    out.luminance[i] = float(y);
    out.noise[i] = float(std::sqrt(var));
    for (size_t c = 0; colors && c < 3; ++c) {
      double v = 0.0;
      for (size_t k = 0; k < refs.size(); ++k) v += weight[k] / total * refs[k].color[3 * i + c];
      out.color[3 * i + c] = float(v);
    }
    for (size_t c = 0; ratios && c < 2; ++c) {
      double v = 0.0;
      for (size_t k = 0; k < refs.size(); ++k) {
        const double w = weight[k] / total, s = refs[k].ratio_noise[2 * i + c];
        v += w * w * s * s;
      }
      out.ratio_noise[2 * i + c] = float(std::sqrt(v));
    }
  }
  return out;
}

}  // namespace cr
