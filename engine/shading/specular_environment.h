#pragma once
// A prefiltered environment for glossy reflections (the radiance half of the
// split sum, Karis 2013): linear RGB radiance (cd/m^2) over all directions in
// octahedral maps, level k prefiltered for GGX with perceptual roughness
// r_k = k / (levels - 1) (level 0: the unfiltered radiance, a mirror), read
// bilinearly inside a level and linearly between levels.
//
// Octahedral mapping with world +Y as the pole: the upper hemisphere fills
// the inner diamond of the unit square, the lower one the four corners. Each
// level stores a one-texel border holding the texels across the square's
// edge (an edge folds onto itself about its midpoint, the corners meet), so a
// bilinear fetch needs no wrapping and is continuous over the whole sphere.
// The engine knows no sky: a plugin builds one (environment_prefilter.h) and
// publishes it through LightEnvironment::specular.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

// Unit direction -> [0, 1]^2, and back (the result normalised).
glm::vec2 octahedral_encode(const glm::vec3& d);
glm::vec3 octahedral_decode(glm::vec2 uv);

class SpecularEnvironment {
 public:
  // sizes[k]: level k's width and height in texels (>= 1), one entry per level.
  explicit SpecularEnvironment(std::vector<int> sizes);

  int levels() const { return int(sizes_.size()); }
  int size(int level) const { return sizes_[size_t(level)]; }
  // Perceptual roughness level `level` is prefiltered for.
  float roughness(int level) const { return levels() > 1 ? float(level) / float(levels() - 1) : 0.0f; }
  // Direction through the centre of texel (x, y) of a size x size level.
  static glm::vec3 texel_direction(int size, int x, int y);

  glm::vec3 texel(int level, int x, int y) const;
  void set_texel(int level, int x, int y, const glm::vec3& radiance);
  // Copies the texels across the edges into the level's border; call once
  // all of its texels are set, before sampling it.
  void fill_border(int level);

  // Radiance arriving from direction dir (need not be unit) at fractional
  // level `level` (clamped to [0, levels - 1]): bilinear in the two nearest
  // levels, linear between them.
  glm::vec3 sample_level(const glm::vec3& dir, float level) const;
  // The prefiltered radiance for perceptual roughness r: sample_level(dir, r (levels - 1)).
  glm::vec3 sample(const glm::vec3& dir, float roughness) const;
  // sample() of n directions (dx, dy, dz)[i] and roughnesses into r/g/b[i], bit for bit.
  void sample_batch(size_t n, const float* dx, const float* dy, const float* dz, const float* roughness, float* r,
                    float* g, float* b) const;

  // The reduced-precision form (the mobile profile's q15 LUTs): every texel
  // rounded to 15-bit fixed point with one scale for the whole environment
  // (its brightest channel at code 32767), the float texels rounded in place,
  // and from then on sample_level() and sample_batch() blend the codes in
  // 16-bit lanes (fx::lerp_q15: along y, then x, then between the levels)
  // and decode once. Call once every level is complete.
  void quantize_q15();
  bool quantized() const { return !codes_.empty(); }
  float code_scale() const { return scale_; }  // the value of code 32768 (Q15Scale::scale)

 private:
  size_t padded_index(int level, int px, int py) const {  // border-inclusive coordinates in [0, size + 1]
    return size_t(offsets_[size_t(level)]) + size_t(py) * size_t(sizes_[size_t(level)] + 2) + size_t(px);
  }
  std::vector<int> sizes_;
  std::vector<float> fsizes_;
  std::vector<int> offsets_;     // first padded texel of each level (int: the vectorised lookup's indices)
  std::vector<float> rgba_;      // padded texels, RGB + pad (one 16-byte load each)
  std::vector<uint16_t> codes_;  // the same texels in q15 (quantize_q15), RGB + pad: two texels a 16-byte load
  float scale_ = 1.0f;
};

}  // namespace cr
