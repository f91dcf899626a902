#include "engine/shading/specular_environment.h"

#include <cmath>

namespace cr {

namespace {

inline float sign_of(float x) { return x >= 0.0f ? 1.0f : -1.0f; }  // +1 at 0: the fold's own choice

// Four floats in one SSE register: a texel is RGB + pad, so a bilinear fetch
// is four 16-byte loads and three lerps, not 12 gathers (gathers made the
// vectorised loop 2x slower on the machines measured; docs/atmosphere.md).
typedef float Texel4 __attribute__((vector_size(16)));

inline Texel4 load_texel(const float* p) {
  Texel4 t;
  __builtin_memcpy(&t, p, sizeof(t));
  return t;
}

// Bilinear fetch of one level at unit-square coordinates (u, v), in the
// padded layout: texel centres at (i + 0.5) / size, the border beyond.
inline Texel4 fetch_level(const float* rgba, size_t offset, int size, float fsize, float u, float v) {
  float px = u * fsize + 0.5f, py = v * fsize + 0.5f;  // padded texel coordinates
  const float hi = fsize + 0.5f;
  px = px > 0.5f ? (px < hi ? px : hi) : 0.5f;  // NaN -> 0.5
  py = py > 0.5f ? (py < hi ? py : hi) : 0.5f;
  const int ix = int(px), iy = int(py);  // in [0, size]
  const float wx = px - float(ix), wy = py - float(iy);
  const size_t stride = size_t(size + 2) * 4;
  const float* t00 = rgba + (offset + size_t(iy) * size_t(size + 2) + size_t(ix)) * 4;
  const Texel4 a = load_texel(t00), b = load_texel(t00 + 4);
  const Texel4 c = load_texel(t00 + stride), d = load_texel(t00 + stride + 4);
  const Texel4 top = a + (b - a) * wx, bottom = c + (d - c) * wx;
  return top + (bottom - top) * wy;
}

// The whole lookup for one direction and fractional level.
inline void fetch(const float* rgba, const size_t* offsets, const int* sizes, const float* fsizes, int levels, float x,
                  float y, float z, float level, float& r, float& g, float& b) {
  const float s = std::abs(x) + std::abs(y) + std::abs(z);
  const float inv = s > 0.0f ? 1.0f / s : 0.0f;  // a zero direction reads the +Y pole
  const float px = x * inv, pz = z * inv;
  const bool lower = y * inv < 0.0f;
  const float fx = lower ? (1.0f - std::abs(pz)) * sign_of(px) : px;
  const float fz = lower ? (1.0f - std::abs(px)) * sign_of(pz) : pz;
  const float u = fx * 0.5f + 0.5f, v = fz * 0.5f + 0.5f;
  const float top = float(levels - 1);
  const float l = level > 0.0f ? (level < top ? level : top) : 0.0f;  // NaN -> 0
  const int k0 = int(l);
  const int k1 = k0 + 1 < levels ? k0 + 1 : k0;
  const float w = l - float(k0);
  const Texel4 t0 = fetch_level(rgba, offsets[k0], sizes[k0], fsizes[k0], u, v);
  const Texel4 t1 = fetch_level(rgba, offsets[k1], sizes[k1], fsizes[k1], u, v);
  const Texel4 t = t0 + (t1 - t0) * w;
  r = t[0];
  g = t[1];
  b = t[2];
}

}  // namespace

glm::vec2 octahedral_encode(const glm::vec3& d) {
  const float s = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  const float inv = s > 0.0f ? 1.0f / s : 0.0f;
  const float px = d.x * inv, pz = d.z * inv;
  const bool lower = d.y * inv < 0.0f;
  const float fx = lower ? (1.0f - std::abs(pz)) * sign_of(px) : px;
  const float fz = lower ? (1.0f - std::abs(px)) * sign_of(pz) : pz;
  return {fx * 0.5f + 0.5f, fz * 0.5f + 0.5f};
}

glm::vec3 octahedral_decode(glm::vec2 uv) {
  const float a = 2.0f * uv.x - 1.0f, b = 2.0f * uv.y - 1.0f;
  const float y = 1.0f - std::abs(a) - std::abs(b);
  const float x = y < 0.0f ? (1.0f - std::abs(b)) * sign_of(a) : a;
  const float z = y < 0.0f ? (1.0f - std::abs(a)) * sign_of(b) : b;
  return glm::normalize(glm::vec3(x, y, z));
}

SpecularEnvironment::SpecularEnvironment(std::vector<int> sizes) : sizes_(std::move(sizes)) {
  size_t total = 0;
  for (int s : sizes_) {
    offsets_.push_back(total);
    fsizes_.push_back(float(s));
    total += size_t(s + 2) * size_t(s + 2);
  }
  rgba_.assign(total * 4, 0.0f);
}

glm::vec3 SpecularEnvironment::texel_direction(int size, int x, int y) {
  return octahedral_decode(glm::vec2((float(x) + 0.5f) / float(size), (float(y) + 0.5f) / float(size)));
}

glm::vec3 SpecularEnvironment::texel(int level, int x, int y) const {
  const float* t = &rgba_[padded_index(level, x + 1, y + 1) * 4];
  return {t[0], t[1], t[2]};
}

void SpecularEnvironment::set_texel(int level, int x, int y, const glm::vec3& radiance) {
  float* t = &rgba_[padded_index(level, x + 1, y + 1) * 4];
  t[0] = radiance.r;
  t[1] = radiance.g;
  t[2] = radiance.b;
}

void SpecularEnvironment::fill_border(int level) {
  const int n = size(level);
  for (int py = 0; py < n + 2; ++py)
    for (int px = 0; px < n + 2; ++px) {
      if (px > 0 && px <= n && py > 0 && py <= n) continue;
      // Across a vertical edge, then a horizontal one: the edge's mirror texel (corners: the opposite one).
      int x = px - 1, y = py - 1;
      if (x < 0 || x >= n) {
        x = x < 0 ? 0 : n - 1;
        y = n - 1 - y;
      }
      if (y < 0 || y >= n) {
        y = y < 0 ? 0 : n - 1;
        x = n - 1 - x;
      }
      const size_t from = padded_index(level, x + 1, y + 1) * 4, to = padded_index(level, px, py) * 4;
      for (int c = 0; c < 4; ++c) rgba_[to + size_t(c)] = rgba_[from + size_t(c)];
    }
}

glm::vec3 SpecularEnvironment::sample_level(const glm::vec3& dir, float level) const {
  glm::vec3 out;
  fetch(rgba_.data(), offsets_.data(), sizes_.data(), fsizes_.data(), levels(), dir.x, dir.y, dir.z, level, out.r,
        out.g, out.b);
  return out;
}

glm::vec3 SpecularEnvironment::sample(const glm::vec3& dir, float roughness) const {
  glm::vec3 out;
  sample_batch(1, &dir.x, &dir.y, &dir.z, &roughness, &out.r, &out.g, &out.b);
  return out;
}

void SpecularEnvironment::sample_batch(size_t n, const float* dx, const float* dy, const float* dz,
                                       const float* roughness, float* r, float* g, float* b) const {
  const float* rgba = rgba_.data();
  const size_t* offsets = offsets_.data();
  const int* sizes = sizes_.data();
  const float* fsizes = fsizes_.data();
  const int levels = this->levels();
  const float top = float(levels - 1);
  for (size_t i = 0; i < n; ++i)
    fetch(rgba, offsets, sizes, fsizes, levels, dx[i], dy[i], dz[i], roughness[i] * top, r[i], g[i], b[i]);
}

}  // namespace cr
