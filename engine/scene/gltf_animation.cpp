#include "engine/scene/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <utility>

#include "engine/scene/gltf_accessors.h"

namespace cr {

namespace {

std::optional<AnimationPath> parse_path(const std::string& path) {
  if (path == "translation") return AnimationPath::Translation;
  if (path == "rotation") return AnimationPath::Rotation;
  if (path == "scale") return AnimationPath::Scale;
  if (path == "weights") return AnimationPath::Weights;
  return std::nullopt;
}

Interpolation parse_interpolation(const GltfContext& ctx, const std::string& name, const std::string& label) {
  if (name == "LINEAR") return Interpolation::Linear;
  if (name == "STEP") return Interpolation::Step;
  if (name == "CUBICSPLINE") return Interpolation::CubicSpline;
  ctx.fail(label + " has interpolation \"" + name + "\"; expected LINEAR, STEP or CUBICSPLINE");
}

std::vector<float> load_times(const GltfContext& ctx, int accessor, const std::string& what) {
  const FloatAccessor in = read_float_accessor(ctx, accessor, what, {TINYGLTF_TYPE_SCALAR}, AttributeKind::Scalar);
  for (size_t k = 0; k < in.count; ++k) {
    const float t = in.values[k];
    if (!std::isfinite(t)) ctx.fail(what + ": time " + std::to_string(k) + " is not finite");
    if (k == 0 && t < 0.0f) ctx.fail(what + ": time 0 is " + std::to_string(t) + "; times must be >= 0");
    if (k > 0 && !(t > in.values[k - 1])) {
      ctx.fail(what + ": time " + std::to_string(k) + " (" + std::to_string(t) + " s) does not follow time " +
               std::to_string(k - 1) + " (" + std::to_string(in.values[k - 1]) + " s); times must be strictly increasing");
    }
  }
  return in.values;
}

// The sampler `index` of `anim` as read for a channel on `path`; `targets`
// is the morph target count for weights.
AnimationSampler load_sampler(const GltfContext& ctx, const tinygltf::Animation& anim, int index,
                              const std::string& label, AnimationPath path, size_t targets) {
  if (index < 0 || static_cast<size_t>(index) >= anim.samplers.size()) {
    ctx.fail(label + " sampler " + std::to_string(index) + " out of range (" + std::to_string(anim.samplers.size()) +
             " samplers)");
  }
  const tinygltf::AnimationSampler& src = anim.samplers[index];
  const std::string what = label + " sampler " + std::to_string(index);
  AnimationSampler s;
  s.interpolation = parse_interpolation(ctx, src.interpolation, what);
  s.times = load_times(ctx, src.input, what + " input");
  const bool weights = path == AnimationPath::Weights;
  const int type = weights ? TINYGLTF_TYPE_SCALAR : path == AnimationPath::Rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
  s.components = weights ? static_cast<int>(targets) : path == AnimationPath::Rotation ? 4 : 3;
  const AttributeKind kind =
      path == AnimationPath::Translation || path == AnimationPath::Scale ? AttributeKind::Scalar
                                                                        : AttributeKind::AnimatedRotationOrWeights;
  const FloatAccessor out = read_float_accessor(ctx, src.output, what + " output", {type}, kind);
  const size_t per_key = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const size_t expected_values = s.times.size() * per_key * static_cast<size_t>(s.components);
  if (out.values.size() != expected_values) {
    ctx.fail(what + " output has " + std::to_string(out.count) + " elements; expected " +
             std::to_string(expected_values / static_cast<size_t>(out.components)) + " (" +
             std::to_string(s.times.size()) + " keys" + (per_key == 3 ? " x 3 for CUBICSPLINE" : "") +
             (weights ? " x " + std::to_string(targets) + " morph targets" : "") + ")");
  }
  s.values = out.values;
  for (size_t i = 0; i < s.values.size(); ++i) {
    if (!std::isfinite(s.values[i])) ctx.fail(what + " output value " + std::to_string(i) + " is not finite");
  }
  if (path == AnimationPath::Rotation) {
    for (size_t k = 0; k < s.times.size(); ++k) {
      // The key's value: the middle of (in-tangent, value, out-tangent) for CUBICSPLINE.
      float* q = &s.values[4 * (per_key * k + (per_key == 3 ? 1 : 0))];
      const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
      if (!(len > 1e-6)) ctx.fail(what + " output rotation of key " + std::to_string(k) + " is a zero quaternion");
      // Spline values and tangents belong together and stay as given (the
      // spline's result is normalised); LINEAR and STEP keys are made unit.
      if (per_key == 1) {
        for (int c = 0; c < 4; ++c) q[c] = static_cast<float>(q[c] / len);
      }
    }
  }
  return s;
}

}  // namespace

std::vector<AnimationClip> load_animations(const GltfContext& ctx, const std::vector<SceneNode>& nodes,
                                           const std::vector<MeshDeformation>& deformations) {
  std::vector<AnimationClip> clips;
  size_t ignored = 0;
  for (size_t a = 0; a < ctx.model.animations.size(); ++a) {
    const tinygltf::Animation& anim = ctx.model.animations[a];
    const std::string label = gltf_label("animation", a, anim.name);
    AnimationClip clip;
    clip.name = anim.name;
    std::set<std::pair<int, AnimationPath>> targeted;
    for (size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& ch = anim.channels[c];
      const std::string what = label + " channel " + std::to_string(c);
      const std::optional<AnimationPath> path = parse_path(ch.target_path);
      if (!path) {
        ++ignored;
        continue;
      }
      if (ch.target_node < 0 || static_cast<size_t>(ch.target_node) >= nodes.size()) {
        ctx.fail(what + " target node " + std::to_string(ch.target_node) + " out of range (" +
                 std::to_string(nodes.size()) + " nodes)");
      }
      const SceneNode& node = nodes[ch.target_node];
      const std::string target = what + " (node " + std::to_string(ch.target_node) + " " + ch.target_path + ")";
      if (!targeted.insert({ch.target_node, *path}).second) {
        ctx.fail(target + " animates a property another channel of the animation already animates");
      }
      if (node.rest.matrix) ctx.fail(target + " animates a node given by \"matrix\"; animated nodes need TRS");
      size_t targets = 0;
      if (*path == AnimationPath::Weights) {
        targets = node.mesh >= 0 ? deformations[node.mesh].target_count : 0;
        if (targets == 0) ctx.fail(target + " animates morph weights but the node has no mesh with morph targets");
      }
      AnimationChannel channel;
      channel.node = ch.target_node;
      channel.path = *path;
      channel.sampler = load_sampler(ctx, anim, ch.sampler, what, *path, targets);
      clip.duration_s = std::max(clip.duration_s, double(channel.sampler.times.back()));
      clip.channels.push_back(std::move(channel));
    }
    clips.push_back(std::move(clip));
  }
  if (ignored > 0) {
    ctx.warn(std::to_string(ignored) + " animation channel(s) target a path other than translation, rotation, "
             "scale and weights; ignored");
  }
  return clips;
}

}  // namespace cr
