#include "fog/volume_shadow.h"

#include <cmath>

namespace cr {

VolumeShadow::VolumeShadow(const ShadowMap& map, const glm::dvec3& camera_position) {
  if (map.size <= 0 || map.depth.size() < size_t(map.size) * size_t(map.size)) return;
  size_ = map.size;
  depth_ = map.depth.data();
  // clip = M (rel + camera - origin). Texel coordinates (centres at +0.5,
  // minus 0.5 for the bilinear footprint): x = (clip.x + 1)/2 size - 0.5,
  // y = (1 - clip.y)/2 size - 0.5. Depth gets ShadowMap's constant bias.
  const glm::vec3 offset(camera_position - map.origin);
  const float s = float(size_);
  const float bias = 0.5f * map.texel_world_size / map.depth_range + 1.0f / float(1 << 20);
  glm::mat4 texel(1.0f);
  texel[0][0] = 0.5f * s;
  texel[1][1] = -0.5f * s;
  texel[3][0] = 0.5f * s - 0.5f;
  texel[3][1] = 0.5f * s - 0.5f;
  texel[3][2] = bias;
  bias_ = bias;
  glm::mat4 translate(1.0f);
  translate[3] = glm::vec4(offset, 1.0f);
  to_texel_ = texel * map.light_view_proj * translate;
}

VolumeShadow::Ray VolumeShadow::ray(const glm::vec3& origin_rel, const glm::vec3& direction) const {
  Ray r;
  r.origin = glm::vec3(to_texel_ * glm::vec4(origin_rel, 1.0f));
  r.step = glm::vec3(to_texel_ * glm::vec4(direction, 0.0f));
  return r;
}

float VolumeShadow::visibility(const Ray& r, float t) const {
  if (size_ <= 0) return 1.0f;
  const float tx = r.origin.x + t * r.step.x;
  const float ty = r.origin.y + t * r.step.y;
  const float receiver = r.origin.z + t * r.step.z;
  const float s = float(size_);
  // Outside the map's volume nothing was recorded: lit.
  if (!(tx >= -1.0f && ty >= -1.0f && tx <= s && ty <= s && receiver >= bias_ && receiver <= 1.0f + bias_))
    return 1.0f;
  const float fx = std::floor(tx), fy = std::floor(ty);
  const float ax = tx - fx, ay = ty - fy;
  const int x0 = int(fx), y0 = int(fy);
  auto lit = [&](int x, int y) -> float {
    if (x < 0 || y < 0 || x >= size_ || y >= size_) return 1.0f;
    return depth_[size_t(y) * size_t(size_) + size_t(x)] <= receiver ? 1.0f : 0.0f;
  };
  const float top = lit(x0, y0) + (lit(x0 + 1, y0) - lit(x0, y0)) * ax;
  const float bottom = lit(x0, y0 + 1) + (lit(x0 + 1, y0 + 1) - lit(x0, y0 + 1)) * ax;
  return top + (bottom - top) * ay;
}

}  // namespace cr
