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

}  // namespace cr
