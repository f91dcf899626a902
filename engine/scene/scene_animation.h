#pragma once
// What a glTF file needs to be posed again at another time: the node
// hierarchy with rest transforms and what each node places (meshes with
// their instances, cameras, lights), skins, morph targets and animations.
// pose_scene rewrites a Scene's draws, its per-node deformed mesh copies,
// camera frames, light placements, sun and bounds for one animation time;
// the loader poses the rest pose with it, so load and playback share the
// same code.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/scene/scene.h"

namespace cr {

struct SceneDescription;

// A node's local transform: translation, rotation and scale (what
// animations target), or a fixed matrix for a node given by "matrix".
struct NodeTransform {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // unit
  glm::dvec3 scale{1.0};
  std::optional<glm::dmat4> matrix;
  glm::dmat4 local() const;  // T * R * S, or the matrix
};

struct SceneNode {
  std::string name;
  int parent = -1;
  NodeTransform rest;
  int mesh = -1;        // glTF mesh: Scene::meshes[mesh] is its rest shape
  int posed_mesh = -1;  // Scene::meshes index of this node's morphed/skinned copy; -1: draws the rest shape
  int skin = -1;        // SceneAnimation::skins index; -1: not skinned
  std::vector<float> weights;         // morph weights at rest (node's, else the mesh's), one per target
  std::vector<glm::dmat4> instances;  // EXT_mesh_gpu_instancing transforms; empty: drawn once
  int camera = -1;                    // Scene::cameras index placed by this node
  int light = -1;                     // Scene::lights index placed by this node
  bool sun = false;                   // the node places Scene::sun
};

struct SceneSkin {
  std::string name;
  std::vector<int> joints;               // node indices
  std::vector<glm::dmat4> inverse_bind;  // one per joint
};

// One morph target of a primitive: per-vertex deltas, each stream empty
// when the target does not displace it.
struct MorphTarget {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec3> tangents;
};

// What deforms one primitive, in the vertex order of its rest Primitive.
struct PrimitiveDeformation {
  std::vector<MorphTarget> targets;
  // Skin influences, one entry per JOINTS_n/WEIGHTS_n set, each per vertex;
  // weights are normalised to sum to 1 over all sets.
  std::vector<std::vector<glm::u16vec4>> joints;
  std::vector<std::vector<glm::vec4>> weights;
  uint32_t max_joint = 0;           // largest joint index used (checked against each skin)
  bool flat_normals = false;        // no NORMAL in the file: flat normals recomputed from the pose
  bool generated_tangents = false;  // no TANGENT in the file: tangents recomputed from the pose
  int tangent_texcoord = 0;         // the UV set generated tangents follow (the normal map's)
  bool skinnable() const { return !joints.empty(); }
};

struct MeshDeformation {
  size_t target_count = 0;                     // morph targets, equal for every primitive
  std::vector<PrimitiveDeformation> primitives;  // as Mesh::primitives
};

enum class Interpolation : uint8_t { Linear, Step, CubicSpline };

// Keyframes of one animated property: `components` values per key
// (CUBICSPLINE: in-tangent, value, out-tangent per key, each `components`).
struct AnimationSampler {
  std::vector<float> times;  // seconds, strictly increasing, >= 0
  std::vector<float> values;
  int components = 0;
  Interpolation interpolation = Interpolation::Linear;
};

enum class AnimationPath : uint8_t { Translation, Rotation, Scale, Weights };

struct AnimationChannel {
  int node = 0;
  AnimationPath path = AnimationPath::Translation;
  AnimationSampler sampler;  // rotations: unit quaternions x, y, z, w
};

struct AnimationClip {
  std::string name;
  std::vector<AnimationChannel> channels;  // at most one per (node, path)
  double duration_s = 0.0;                 // last keyframe time of all channels
};

struct SceneAnimation {
  std::vector<SceneNode> nodes;       // as the glTF nodes
  std::vector<int> update_order;      // every node, each after its parent (world matrices)
  std::vector<int> draw_order;        // the scene's nodes, depth first, children in file order
  std::vector<SceneSkin> skins;
  std::vector<MeshDeformation> deformations;  // per glTF mesh; empty primitives: not deformable
  std::vector<AnimationClip> animations;
};

// Poses `scene` at `time_s` seconds of `animation_data.animations[*animation]`
// (times outside its keyframes hold the first or last key), or at the rest
// pose for nullopt: node transforms and morph weights from the animation,
// then every drawn node's world matrix, its morphed and skinned mesh copy
// (linear blend skinning on the CPU, normals by the inverse-transpose),
// draws (one per primitive and instance), cameras, lights, sun and bounds.
// Node instances (a node without instancing is one) whose world matrix is
// singular or not finite are not drawn; returns their count. Throws
// InputError(scene.source) when a camera or light is placed by a degenerate
// transform.
size_t pose_scene(Scene& scene, const SceneAnimation& animation_data, std::optional<size_t> animation, double time_s);

// The animation a scene file asks for (SceneDescription::animation), by
// index or name; nullopt when it asks for none. Throws InputError naming
// the scene file and the field when the glTF has no such animation.
std::optional<size_t> described_animation(const Scene& scene, const SceneDescription& description);

// Poses a loaded scene as its scene file asks: the chosen animation at its
// time (which the automatic view then frames: Scene::framing_*), else the
// rest pose (as loaded), with one warning when the file has animations that
// are not shown.
void pose_described_scene(Scene& scene, const SceneDescription& description);

}  // namespace cr
