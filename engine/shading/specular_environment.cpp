#include "engine/shading/specular_environment.h"

#include <cmath>

#include "engine/core/fixed_simd.h"
#include "engine/core/q15_scale.h"

namespace cr {

namespace {

inline float sign_of(float x) { return x >= 0.0f ? 1.0f : -1.0f; }  // +1 at 0: the fold's own choice

inline void encode(float x, float y, float z, float& u, float& v) {
  const float s = std::abs(x) + std::abs(y) + std::abs(z);
  const float inv = s > 0.0f ? 1.0f / s : 0.0f;  // a zero direction reads the +Y pole
  const float px = x * inv, pz = z * inv;
  const bool lower = y * inv < 0.0f;
  const float fx = lower ? (1.0f - std::abs(pz)) * sign_of(px) : px;
  const float fz = lower ? (1.0f - std::abs(px)) * sign_of(pz) : pz;
  u = fx * 0.5f + 0.5f;
  v = fz * 0.5f + 0.5f;
}

// Four floats in one SSE register: a texel is RGB + pad, so a bilinear fetch
// is four 16-byte loads and three lerps, not 12 gathers (gathers made the
// vectorised loop 2x slower on the machines measured; docs/atmosphere.md).
typedef float Texel4 __attribute__((vector_size(16)));

inline Texel4 load_texel(const float* p) {
  Texel4 t;
  __builtin_memcpy(&t, p, sizeof(t));
  return t;
}

// Where one level's bilinear fetch reads, at unit-square coordinates (u, v)
// in the padded layout (texel centres at (i + 0.5) / size, the border
// beyond): the first float of its 2x2 taps, the row stride in floats, the weights.
struct LevelTaps {
  int first, row;
  float wx, wy;
};

inline LevelTaps level_taps(int offset, float fsize, float u, float v) {
  float px = u * fsize + 0.5f, py = v * fsize + 0.5f;  // padded texel coordinates
  const float hi = fsize + 0.5f;
  px = px > 0.5f ? (px < hi ? px : hi) : 0.5f;  // NaN -> 0.5
  py = py > 0.5f ? (py < hi ? py : hi) : 0.5f;
  const int ix = int(px), iy = int(py);  // in [0, size]
  const int row = int(fsize) + 2;
  return {(offset + iy * row + ix) * 4, row * 4, px - float(ix), py - float(iy)};
}

// The two levels around fractional level l (clamped to [0, levels - 1]) and the weight between them.
inline void level_pair(int levels, float level, int& k0, int& k1, float& w) {
  const float top = float(levels - 1);
  const float l = level > 0.0f ? (level < top ? level : top) : 0.0f;  // NaN -> 0
  k0 = int(l);
  k1 = k0 + 1 < levels ? k0 + 1 : k0;
  w = l - float(k0);
}

inline Texel4 bilinear(const float* rgba, const LevelTaps& t) {
  const float* t00 = rgba + t.first;
  const Texel4 a = load_texel(t00), b = load_texel(t00 + 4);
  const Texel4 c = load_texel(t00 + t.row), d = load_texel(t00 + t.row + 4);
  const Texel4 top = a + (b - a) * t.wx, bottom = c + (d - c) * t.wx;
  return top + (bottom - top) * t.wy;
}

inline Texel4 trilinear(const float* rgba, const LevelTaps& t0, const LevelTaps& t1, float w) {
  const Texel4 a = bilinear(rgba, t0), b = bilinear(rgba, t1);
  return a + (b - a) * w;
}

// trilinear() from q15 codes (the same tap offsets: 4 codes a texel): a
// row's two taps are one 16-byte load, so the rows are blended first (8
// lanes: both taps), then the left tap with the right one, then the levels.
inline fx::U16x8 bilinear_q15(const uint16_t* codes, const LevelTaps& t) {
  fx::U16x8 top, bottom;
  __builtin_memcpy(&top, codes + t.first, sizeof top);
  __builtin_memcpy(&bottom, codes + t.first + t.row, sizeof bottom);
  const fx::U16x8 rows = fx::lerp_q15(top, bottom, fx::I16x8{} + fx::weight_q15(t.wy));
  const fx::U16x8 swapped = __builtin_shufflevector(rows, rows, 4, 5, 6, 7, 0, 1, 2, 3);
  return fx::lerp_q15(rows, swapped, fx::I16x8{} + fx::weight_q15(t.wx));  // lanes 0-3: the texel
}

inline Texel4 trilinear_q15(const uint16_t* codes, float scale, const LevelTaps& t0, const LevelTaps& t1, float w) {
  const fx::U16x8 a = bilinear_q15(codes, t0), b = bilinear_q15(codes, t1);
  Texel4 lo, hi;
  fx::decode_q15(fx::lerp_q15(a, b, fx::I16x8{} + fx::weight_q15(w)), lo, hi);
  return lo * scale;
}

}  // namespace

glm::vec2 octahedral_encode(const glm::vec3& d) {
  glm::vec2 uv;
  encode(d.x, d.y, d.z, uv.x, uv.y);
  return uv;
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
    offsets_.push_back(int(total));
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
  float u, v, w;
  int k0, k1;
  encode(dir.x, dir.y, dir.z, u, v);
  level_pair(levels(), level, k0, k1, w);
  const LevelTaps t0 = level_taps(offsets_[size_t(k0)], fsizes_[size_t(k0)], u, v);
  const LevelTaps t1 = level_taps(offsets_[size_t(k1)], fsizes_[size_t(k1)], u, v);
  const Texel4 t = quantized() ? trilinear_q15(codes_.data(), scale_, t0, t1, w) : trilinear(rgba_.data(), t0, t1, w);
  return {t[0], t[1], t[2]};
}

glm::vec3 SpecularEnvironment::sample(const glm::vec3& dir, float roughness) const {
  glm::vec3 out;
  sample_batch(1, &dir.x, &dir.y, &dir.z, &roughness, &out.r, &out.g, &out.b);
  return out;
}

// sample_level's steps over many points, in loops that vectorise (16 lanes
// at AVX-512) up to the taps' 16-byte loads: per chunk, the coordinates and
// level pairs; each level's size and offset set where it is used (GCC 12
// vectorises no gather from these tables: "no vectype" once the index's range
// is known); the taps and weights; then the loads, point by point.
void SpecularEnvironment::sample_batch(size_t n, const float* dx, const float* dy, const float* dz,
                                       const float* roughness, float* r, float* g, float* b) const {
  const float* rgba = rgba_.data();
  const int levels = this->levels();
  const float top = float(levels - 1);
  constexpr size_t kChunk = 64;
  float u[kChunk], v[kChunk], w[kChunk], fsize0[kChunk], fsize1[kChunk];
  int k0[kChunk], k1[kChunk], offset0[kChunk], offset1[kChunk];
  int first0[kChunk], row0[kChunk], first1[kChunk], row1[kChunk];  // LevelTaps as arrays: stored 16 lanes at once
  float wx0[kChunk], wy0[kChunk], wx1[kChunk], wy1[kChunk];
  for (size_t start = 0; start < n; start += kChunk) {
    const size_t m = n - start < kChunk ? n - start : kChunk;
    const float *x = dx + start, *y = dy + start, *z = dz + start, *rough = roughness + start;
    for (size_t i = 0; i < m; ++i) {
      encode(x[i], y[i], z[i], u[i], v[i]);
      level_pair(levels, rough[i] * top, k0[i], k1[i], w[i]);
    }
    for (int k = 0; k < levels; ++k) {
      const int offset = offsets_[size_t(k)];
      const float fsize = fsizes_[size_t(k)];
      for (size_t i = 0; i < m; ++i) {
        offset0[i] = k0[i] == k ? offset : offset0[i];
        fsize0[i] = k0[i] == k ? fsize : fsize0[i];
        offset1[i] = k1[i] == k ? offset : offset1[i];
        fsize1[i] = k1[i] == k ? fsize : fsize1[i];
      }
    }
    for (size_t i = 0; i < m; ++i) {
      const LevelTaps t0 = level_taps(offset0[i], fsize0[i], u[i], v[i]);
      const LevelTaps t1 = level_taps(offset1[i], fsize1[i], u[i], v[i]);
      first0[i] = t0.first;
      row0[i] = t0.row;
      wx0[i] = t0.wx;
      wy0[i] = t0.wy;
      first1[i] = t1.first;
      row1[i] = t1.row;
      wx1[i] = t1.wx;
      wy1[i] = t1.wy;
    }
    const uint16_t* codes = codes_.data();
    for (size_t i = 0; i < m; ++i) {
      const LevelTaps t0{first0[i], row0[i], wx0[i], wy0[i]}, t1{first1[i], row1[i], wx1[i], wy1[i]};
      const Texel4 t = codes ? trilinear_q15(codes, scale_, t0, t1, w[i]) : trilinear(rgba, t0, t1, w[i]);
      r[start + i] = t[0];
      g[start + i] = t[1];
      b[start + i] = t[2];
    }
  }
}

void SpecularEnvironment::quantize_q15() {
  const Q15Scale scale = q15_scale_for(max_value(rgba_.data(), rgba_.size(), 1));
  scale_ = scale.scale;
  codes_.resize(rgba_.size());
  for (size_t i = 0; i < rgba_.size(); ++i) {
    codes_[i] = i % 4 == 3 ? 0 : to_q15(rgba_[i], scale);  // the pad lanes stay 0
    rgba_[i] = from_q15(codes_[i], scale);
  }
}

}  // namespace cr
