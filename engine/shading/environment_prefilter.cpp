#include "engine/shading/environment_prefilter.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "engine/shading/brdf.h"
#include "engine/shading/ggx_sampling.h"

namespace cr {

namespace {

std::vector<int> pyramid_sizes(int size) {
  std::vector<int> s;
  for (int n = size; n >= 1; n /= 2) s.push_back(n);
  return s;
}

}  // namespace

std::vector<int> EnvironmentPrefilter::level_sizes(int size, int levels) {
  std::vector<int> s{size};
  for (int k = 1; k < levels; ++k) {
    const float r = float(k) / float(levels - 1);
    const float want = std::ceil(3.545f / (r * r));  // sqrt(4 pi) / alpha
    const int n = int(std::bit_ceil(uint32_t(std::min(want, float(size)))));
    s.push_back(std::min(size, std::max(8, n)));
  }
  return s;
}

EnvironmentPrefilter::EnvironmentPrefilter(int size, int levels, int samples)
    : size_(size),
      env_(std::make_shared<SpecularEnvironment>(level_sizes(size, levels))),
      pyramid_(pyramid_sizes(size)) {
  if (size < 1 || !std::has_single_bit(uint32_t(size)) || levels < 1 || samples < 1)
    throw std::invalid_argument("EnvironmentPrefilter: size must be a power of two, levels and samples >= 1");
  const float texel_solid_angle = 4.0f * kPi / float(size * size);
  const float top_mip = float(pyramid_.levels() - 1);
  for (int k = 1; k < levels; ++k) {
    LevelSamples ls;
    ls.first_item = size_t(size) + prefiltered_texels_;
    const float alpha = std::max(env_->roughness(k) * env_->roughness(k), kMinRoughness * kMinRoughness);
    const int count = samples * (size / env_->size(k));
    double weight = 0.0;
    for (int i = 0; i < count; ++i) {
      const glm::vec3 h = ggx_half_vector(hammersley(uint32_t(i), uint32_t(count)), alpha);
      const glm::vec3 l(2.0f * h.z * h.x, 2.0f * h.z * h.y, 2.0f * h.z * h.z - 1.0f);  // reflect(-n, h)
      if (l.z <= 0.0f) continue;
      // pdf(l) = D (n.h) / (4 v.h) = D / 4 with v = n; the sample stands for 1 / (samples pdf) sr.
      const float pdf = ggx_distribution(h.z, alpha) * 0.25f;
      const float mip = 0.5f * std::log2(1.0f / (float(count) * pdf * texel_solid_angle));
      ls.l.emplace_back(l, std::clamp(mip, 0.0f, top_mip));
      weight += double(l.z);
    }
    ls.inv_weight_sum = weight > 0.0 ? float(1.0 / weight) : 0.0f;
    ls.texels = size_t(env_->size(k)) * size_t(env_->size(k));
    prefiltered_texels_ += ls.texels;
    samples_.push_back(std::move(ls));
  }
  total_cost_ = uint64_t(size) * uint64_t(size);
  for (const LevelSamples& ls : samples_) total_cost_ += uint64_t(ls.texels) * ls.l.size();
}

size_t EnvironmentPrefilter::slice_begin(int s, int slices) const {
  const uint64_t target = total_cost_ * uint64_t(s) / uint64_t(slices);
  const uint64_t row = uint64_t(size_);
  if (target <= row * row) return size_t((target + row - 1) / row);
  uint64_t cost = row * row;
  size_t item = size_t(size_);
  for (const LevelSamples& ls : samples_) {
    const uint64_t per = std::max<uint64_t>(ls.l.size(), 1);
    if (target <= cost + per * ls.texels) return item + size_t((target - cost + per - 1) / per);
    cost += per * ls.texels;
    item += ls.texels;
  }
  return work_items();
}

void EnvironmentPrefilter::base_row(int y, const Radiance& radiance) {
  thread_local std::vector<float> dx, dy, dz;
  thread_local std::vector<glm::vec3> out;
  for (auto* v : {&dx, &dy, &dz}) v->resize(size_t(size_));
  out.resize(size_t(size_));
  for (int x = 0; x < size_; ++x) {
    const glm::vec3 d = SpecularEnvironment::texel_direction(size_, x, y);
    dx[size_t(x)] = d.x;
    dy[size_t(x)] = d.y;
    dz[size_t(x)] = d.z;
  }
  radiance(size_t(size_), dx.data(), dy.data(), dz.data(), out.data());
  for (int x = 0; x < size_; ++x) {
    env_->set_texel(0, x, y, out[size_t(x)]);
    pyramid_.set_texel(0, x, y, out[size_t(x)]);
  }
}

void EnvironmentPrefilter::build_pyramid() {
  env_->fill_border(0);
  pyramid_.fill_border(0);
  for (int m = 1; m < pyramid_.levels(); ++m) {
    const int n = pyramid_.size(m);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::vec3 s = (pyramid_.texel(m - 1, 2 * x, 2 * y) + pyramid_.texel(m - 1, 2 * x + 1, 2 * y)) +
                            (pyramid_.texel(m - 1, 2 * x, 2 * y + 1) + pyramid_.texel(m - 1, 2 * x + 1, 2 * y + 1));
        pyramid_.set_texel(m, x, y, 0.25f * s);
      }
    pyramid_.fill_border(m);
  }
}

void EnvironmentPrefilter::prefilter_texel(size_t item) {
  size_t k = samples_.size();
  while (samples_[k - 1].first_item > item) --k;  // level k (samples_[k - 1])
  const LevelSamples& ls = samples_[k - 1];
  const int n = env_->size(int(k));
  const size_t t = item - ls.first_item;
  const int x = int(t % size_t(n)), y = int(t / size_t(n));
  const glm::vec3 r = SpecularEnvironment::texel_direction(n, x, y);
  glm::vec3 tx, ty;
  orthonormal_frame(r, tx, ty);
  glm::vec3 sum(0.0f);
  for (const glm::vec4& s : ls.l) sum += s.z * pyramid_.sample_level(s.x * tx + s.y * ty + s.z * r, s.w);
  env_->set_texel(int(k), x, y, sum * ls.inv_weight_sum);
}

void EnvironmentPrefilter::run(size_t begin, size_t end, const Radiance& radiance, JobSystem& jobs,
                               const std::string& job_name) {
  if (begin != done_ || end < begin || end > work_items())
    throw std::logic_error("EnvironmentPrefilter::run: items must be run in order");
  const size_t base = size_t(size_);
  if (begin < base) {
    const size_t e = std::min(end, base);
    jobs.parallel_for(job_name, e - begin, 1, [&](size_t b, size_t f) {
      for (size_t i = begin + b; i < begin + f; ++i) base_row(int(i), radiance);
    });
    if (e == base) build_pyramid();
  }
  const size_t b = std::max(begin, base);
  if (end > b)
    jobs.parallel_for(job_name, end - b, 16, [&](size_t x, size_t y) {
      for (size_t i = b + x; i < b + y; ++i) prefilter_texel(i);
    });
  // Each level's border once its last texel is done.
  for (size_t k = 0; k < samples_.size(); ++k) {
    const size_t last = samples_[k].first_item + size_t(env_->size(int(k + 1))) * size_t(env_->size(int(k + 1)));
    if (end >= last && begin < last) env_->fill_border(int(k + 1));
  }
  done_ = end;
}

std::shared_ptr<const SpecularEnvironment> prefilter_environment(int size, int levels, int samples,
                                                                 const EnvironmentPrefilter::Radiance& radiance,
                                                                 JobSystem& jobs) {
  EnvironmentPrefilter p(size, levels, samples);
  p.run(0, p.work_items(), radiance, jobs, "environment.prefilter");
  return p.result();
}

}  // namespace cr
