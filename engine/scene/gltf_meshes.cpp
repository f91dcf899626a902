#include "engine/scene/gltf_meshes.h"

#include <cmath>
#include <numeric>
#include <optional>

#include "engine/scene/gltf_accessors.h"
#include "engine/scene/gltf_morph.h"
#include "engine/scene/gltf_skin.h"
#include "engine/scene/mesh_generation.h"

namespace cr {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Whether a texture of the material reads texture coordinate set `set`.
bool uses_texcoords(const Material& m, int set) {
  for (const TextureRef* t : {&m.base_color, &m.metallic_roughness, &m.normal, &m.occlusion, &m.emissive}) {
    if (t->valid() && t->texcoord == set) return true;
  }
  return false;
}

template <typename Vec>
std::vector<Vec> to_vectors(const FloatAccessor& a) {
  constexpr int n = Vec::length();
  std::vector<Vec> out(a.count);
  for (size_t i = 0; i < a.count; ++i) {
    for (int c = 0; c < n; ++c) out[i][c] = a.values[i * n + c];
  }
  return out;
}

class PrimitiveLoader {
 public:
  PrimitiveLoader(const GltfContext& ctx, const std::vector<Material>& materials, std::string label)
      : ctx_(ctx), materials_(materials), label_(std::move(label)) {}

  // nullopt for a primitive that is not rendered.
  std::optional<Primitive> load(const tinygltf::Primitive& src) {
    int mode = src.mode == -1 ? TINYGLTF_MODE_TRIANGLES : src.mode;
    if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
      ctx_.fail(label_ + " has invalid mode " + std::to_string(mode));
    }
    auto pos_it = src.attributes.find("POSITION");
    if (pos_it == src.attributes.end()) return std::nullopt;  // the spec says: not rendered
    Primitive p;
    p.positions = to_vectors<glm::vec3>(read_float_accessor(ctx_, pos_it->second, attr("POSITION"),
                                                            {TINYGLTF_TYPE_VEC3}, AttributeKind::Position));
    const size_t n = p.positions.size();
    for (size_t v = 0; v < n; ++v) {
      if (!finite(p.positions[v])) ctx_.fail(attr("POSITION") + ": vertex " + std::to_string(v) + " is not finite (NaN or Inf)");
    }
    for (const auto& [name, accessor] : src.attributes) {
      size_t count = check_accessor(ctx_, accessor, attr(name));
      if (count != n) {
        ctx_.fail(attr(name) + " has " + std::to_string(count) + " elements but POSITION has " + std::to_string(n));
      }
    }
    if (mode < TINYGLTF_MODE_TRIANGLES) return std::nullopt;  // points and lines are not rendered

    p.indices = read_indices(src, mode, n);
    p.material = src.material;
    if (src.material < -1 || (src.material >= 0 && static_cast<size_t>(src.material) >= materials_.size())) {
      ctx_.fail(label_ + " has material " + std::to_string(src.material) + " out of range (" +
                std::to_string(materials_.size()) + " materials)");
    }
    const Material* material = src.material >= 0 ? &materials_[src.material] : nullptr;

    p.texcoords = load_texcoords(src, 0, material);
    p.texcoords1 = load_texcoords(src, 1, material);
    if (auto it = src.attributes.find("COLOR_0"); it != src.attributes.end()) {
      FloatAccessor colors = read_float_accessor(ctx_, it->second, attr("COLOR_0"),
                                                 {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, AttributeKind::Color);
      p.colors.resize(n);
      for (size_t v = 0; v < n; ++v) {
        glm::vec4 c(1.0f);
        for (int k = 0; k < colors.components; ++k) c[k] = colors.values[v * colors.components + k];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) {
          ctx_.fail(attr("COLOR_0") + ": vertex " + std::to_string(v) + " is not finite (NaN or Inf)");
        }
        p.colors[v] = c;
      }
    }
    MorphTargets morph = load_morph_targets(ctx_, src, n, label_);
    deformation_.targets = std::move(morph.targets);
    ignored_morph_attributes_ = morph.ignored_attributes;
    load_skin_influences(ctx_, src, n, label_, deformation_);
    const bool deformable = !deformation_.targets.empty() || deformation_.skinnable();
    const bool has_normals = src.attributes.count("NORMAL") > 0;
    // Flat normals need a vertex per corner where a vertex joins faces of
    // different orientations; a deformable primitive's faces may disagree in
    // any pose.
    if (!has_normals && (deformable || !faces_agree_at_vertices(p.positions, p.indices))) unweld(p, deformation_);
    load_normals(src, p);
    const bool needs_tangents = material && material->normal.valid();
    const std::vector<glm::vec2>& tangent_uv = material && material->normal.texcoord == 1 ? p.texcoords1 : p.texcoords;
    if (has_normals) {
      load_tangents(src, p, needs_tangents, tangent_uv);
    } else if (needs_tangents) {
      // glTF: without NORMAL, provided tangents must be ignored too.
      p.tangents = generate_tangents(p.positions, p.normals, tangent_uv, p.indices);
      generated_tangents_ = true;
    }
    deformation_.flat_normals = !has_normals;
    deformation_.generated_tangents = generated_tangents_;
    deformation_.tangent_texcoord = material ? material->normal.texcoord : 0;

    p.bounds_min = p.bounds_max = p.positions[0];
    for (const glm::vec3& v : p.positions) {
      p.bounds_min = glm::min(p.bounds_min, v);
      p.bounds_max = glm::max(p.bounds_max, v);
    }
    return p;
  }

  // Which fallbacks this primitive took (the loader warns once per file).
  bool generated_normals() const { return generated_normals_; }
  bool generated_tangents() const { return generated_tangents_; }
  size_t ignored_morph_attributes() const { return ignored_morph_attributes_; }
  // Morph targets and skin influences of the loaded primitive.
  PrimitiveDeformation& deformation() { return deformation_; }

 private:
  std::string attr(const std::string& name) const { return label_ + " attribute " + name; }

  // TEXCOORD_<set>, required when a texture of the material reads it; empty
  // when absent and unused.
  std::vector<glm::vec2> load_texcoords(const tinygltf::Primitive& src, int set, const Material* material) {
    const std::string name = "TEXCOORD_" + std::to_string(set);
    auto it = src.attributes.find(name);
    if (it == src.attributes.end()) {
      if (material && uses_texcoords(*material, set)) {
        ctx_.fail(label_ + " has no " + name + " but a texture of its material " + std::to_string(src.material) +
                  " reads it");
      }
      return {};
    }
    std::vector<glm::vec2> uv = to_vectors<glm::vec2>(
        read_float_accessor(ctx_, it->second, attr(name), {TINYGLTF_TYPE_VEC2}, AttributeKind::Texcoord));
    for (size_t v = 0; v < uv.size(); ++v) {
      if (!std::isfinite(uv[v].x) || !std::isfinite(uv[v].y)) {
        ctx_.fail(attr(name) + ": vertex " + std::to_string(v) + " is not finite (NaN or Inf)");
      }
    }
    return uv;
  }

  // One vertex per triangle corner (streams copied, indices 0..3T-1): glTF
  // asks for flat normals where a primitive has none.
  static void unweld(Primitive& p, PrimitiveDeformation& d) {
    auto expand = [&p](auto& stream) {
      if (stream.empty()) return;
      std::remove_reference_t<decltype(stream)> out(p.indices.size());
      for (size_t i = 0; i < p.indices.size(); ++i) out[i] = stream[p.indices[i]];
      stream = std::move(out);
    };
    expand(p.positions);
    expand(p.texcoords);
    expand(p.texcoords1);
    expand(p.colors);
    for (MorphTarget& t : d.targets) {
      expand(t.positions);
      expand(t.normals);
      expand(t.tangents);
    }
    for (std::vector<glm::u16vec4>& set : d.joints) expand(set);
    for (std::vector<glm::vec4>& set : d.weights) expand(set);
    std::iota(p.indices.begin(), p.indices.end(), 0u);
  }

  std::vector<uint32_t> read_indices(const tinygltf::Primitive& src, int mode, size_t vertex_count) {
    std::vector<uint32_t> idx;
    if (src.indices >= 0) {
      idx = read_index_accessor(ctx_, src.indices, label_ + " indices");
      for (size_t i = 0; i < idx.size(); ++i) {
        if (idx[i] >= vertex_count) {
          ctx_.fail(label_ + " indices: index " + std::to_string(i) + " has value " + std::to_string(idx[i]) +
                    ", out of range for " + std::to_string(vertex_count) + " vertices");
        }
      }
    } else if (src.indices == -1) {
      idx.resize(vertex_count);
      std::iota(idx.begin(), idx.end(), 0u);
    } else {
      ctx_.fail(label_ + " has invalid indices accessor " + std::to_string(src.indices));
    }
    const char* what = src.indices >= 0 ? "index count" : "vertex count";
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (idx.size() % 3 != 0) {
        ctx_.fail(label_ + " is a triangle list but its " + what + " " + std::to_string(idx.size()) +
                  " is not a multiple of 3");
      }
      return idx;
    }
    if (idx.size() < 3) {
      ctx_.fail(label_ + " is a triangle strip/fan with " + what + " " + std::to_string(idx.size()) + " (needs at least 3)");
    }
    return mode == TINYGLTF_MODE_TRIANGLE_STRIP ? triangulate_strip(idx) : triangulate_fan(idx);
  }

  // File normals are used where usable; zero-length or non-finite ones (a known
  // exporter fault) are replaced by generated normals, with a warning, rather
  // than rejecting an otherwise valid model.
  void load_normals(const tinygltf::Primitive& src, Primitive& p) {
    auto it = src.attributes.find("NORMAL");
    if (it == src.attributes.end()) {
      p.normals = generate_normals(p.positions, p.indices);  // flat: the primitive was unwelded
      generated_normals_ = true;
      return;
    }
    p.normals = to_vectors<glm::vec3>(read_float_accessor(ctx_, it->second, attr("NORMAL"), {TINYGLTF_TYPE_VEC3}, AttributeKind::Normal));
    std::vector<glm::vec3> generated;
    size_t bad = 0;
    for (size_t v = 0; v < p.normals.size(); ++v) {
      float len = glm::length(p.normals[v]);
      if (std::isfinite(len) && len > 1e-12f && finite(p.normals[v])) {
        p.normals[v] /= len;
        continue;
      }
      if (generated.empty()) generated = generate_normals(p.positions, p.indices);
      p.normals[v] = generated[v];
      ++bad;
    }
    if (bad > 0) {
      ctx_.warn(attr("NORMAL") + ": " + std::to_string(bad) + " of " + std::to_string(p.normals.size()) +
                " normals are zero-length or not finite; replaced by generated normals");
    }
  }

  void load_tangents(const tinygltf::Primitive& src, Primitive& p, bool needed, const std::vector<glm::vec2>& uv) {
    auto it = src.attributes.find("TANGENT");
    if (it == src.attributes.end()) {
      if (needed) {
        p.tangents = generate_tangents(p.positions, p.normals, uv, p.indices);
        generated_tangents_ = true;
      }
      return;
    }
    FloatAccessor t = read_float_accessor(ctx_, it->second, attr("TANGENT"), {TINYGLTF_TYPE_VEC4}, AttributeKind::Tangent);
    p.tangents = to_vectors<glm::vec4>(t);
    std::vector<glm::vec4> generated;
    size_t bad = 0;
    for (size_t v = 0; v < p.tangents.size(); ++v) {
      glm::vec4& tv = p.tangents[v];
      glm::vec3 xyz(tv);
      // Orthogonalise against the (possibly replaced) normal, as the shader assumes.
      xyz -= p.normals[v] * glm::dot(p.normals[v], xyz);
      float len = glm::length(xyz);
      if (std::isfinite(len) && len > 1e-12f && std::isfinite(tv.w)) {
        tv = glm::vec4(xyz / len, tv.w < 0.0f ? -1.0f : 1.0f);
        continue;
      }
      if (generated.empty()) generated = generate_tangents(p.positions, p.normals, uv, p.indices);
      tv = generated[v];
      ++bad;
    }
    if (bad > 0) {
      ctx_.warn(attr("TANGENT") + ": " + std::to_string(bad) + " of " + std::to_string(p.tangents.size()) +
                " tangents are degenerate or not finite; replaced by generated tangents");
    }
  }

  const GltfContext& ctx_;
  const std::vector<Material>& materials_;
  std::string label_;
  bool generated_normals_ = false;
  bool generated_tangents_ = false;
  size_t ignored_morph_attributes_ = 0;
  PrimitiveDeformation deformation_;
};

}  // namespace

GltfMeshes load_meshes(const GltfContext& ctx, const std::vector<Material>& materials) {
  GltfMeshes out;
  size_t skipped = 0, flat = 0, tangents = 0, ignored_morph_attributes = 0;
  for (size_t mi = 0; mi < ctx.model.meshes.size(); ++mi) {
    const tinygltf::Mesh& src = ctx.model.meshes[mi];
    Mesh mesh;
    mesh.name = src.name;
    MeshDeformation deformation;
    deformation.target_count = mesh_target_count(ctx, mi);
    std::vector<int> index_map;
    for (size_t pi = 0; pi < src.primitives.size(); ++pi) {
      PrimitiveLoader loader(ctx, materials, gltf_label("mesh", mi, src.name) + " primitive " + std::to_string(pi));
      std::optional<Primitive> p = loader.load(src.primitives[pi]);
      flat += loader.generated_normals();
      tangents += loader.generated_tangents();
      ignored_morph_attributes += loader.ignored_morph_attributes();
      if (p) {
        index_map.push_back(static_cast<int>(mesh.primitives.size()));
        mesh.primitives.push_back(std::move(*p));
        deformation.primitives.push_back(std::move(loader.deformation()));
      } else {
        index_map.push_back(-1);
        ++skipped;
      }
    }
    out.meshes.push_back(std::move(mesh));
    out.primitive_index.push_back(std::move(index_map));
    out.deformations.push_back(std::move(deformation));
  }
  if (skipped > 0) {
    ctx.warn(std::to_string(skipped) + " primitive(s) are points, lines or have no POSITION; they are not rendered");
  }
  if (flat > 0) ctx.warn(std::to_string(flat) + " primitive(s) have no NORMAL; flat normals are generated");
  if (ignored_morph_attributes > 0) {
    ctx.warn(std::to_string(ignored_morph_attributes) + " morph target attribute(s) other than POSITION, NORMAL and "
             "TANGENT are ignored");
  }
  if (tangents > 0) {
    ctx.warn(std::to_string(tangents) + " normal-mapped primitive(s) have no TANGENT; tangents are generated "
             "(MikkTSpace convention)");
  }
  return out;
}

}  // namespace cr
