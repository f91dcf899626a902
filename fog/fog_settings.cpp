#include "fog/fog_settings.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/error.h"
#include "engine/core/json_input.h"

namespace cr {

namespace {

constexpr double kHuge = 1e30;
const NumberRange kPositive{0.0, kHuge, true, false};
const NumberRange kNonNegative{0.0, kHuge};
const NumberRange kUnit{0.0, 1.0};
const NumberRange kAnyFinite{-kHuge, kHuge};
const NumberRange kAnisotropy{-0.999, 0.999};
// Mean free paths: from 1 mm (extinction 1000 /m, opaque within a froxel) to
// 1e30 m, so that the extinction 1 / mfp is a normal float (1e-45 m would
// overflow it to infinity).
const NumberRange kMeanFreePath{1e-3, kHuge};

glm::vec3 to_vec3(const glm::dvec3& v) { return glm::vec3(v); }

FogBlend parse_blend(const JsonObject& o, const char* key) {
  const std::string s = o.string(key);
  if (s == "overwrite") return FogBlend::Overwrite;
  if (s == "additive") return FogBlend::Additive;
  if (s == "multiply") return FogBlend::Multiply;
  if (s == "min") return FogBlend::Min;
  if (s == "max") return FogBlend::Max;
  o.fail(key, "must be one of overwrite, additive, multiply, min, max, found \"" + s + "\"");
}

FogNoise parse_noise(const JsonObject& o) {
  o.allow_only({"scale", "octaves", "strength"});
  FogNoise n;
  n.enabled = true;
  if (o.has("scale")) n.scale = float(o.number("scale", {1e-3, kHuge}));
  if (o.has("octaves")) n.octaves = o.integer("octaves", 1, 8);
  if (o.has("strength")) n.strength = float(o.number("strength", kUnit));
  return n;
}

// Rotation from Euler angles in degrees: yaw about Y, then pitch about X,
// then roll about Z (R = Ry * Rx * Rz), the usual order for placed objects.
void axes_from_euler(const glm::dvec3& deg, glm::vec3 axes[3]) {
  const glm::vec3 r = glm::radians(to_vec3(deg));
  glm::mat4 m = glm::rotate(glm::mat4(1.0f), r.y, glm::vec3(0, 1, 0));
  m = glm::rotate(m, r.x, glm::vec3(1, 0, 0));
  m = glm::rotate(m, r.z, glm::vec3(0, 0, 1));
  for (int i = 0; i < 3; ++i) axes[i] = glm::normalize(glm::vec3(m[i]));
}

void parse_axes(const JsonObject& o, glm::vec3 axes[3]) {
  const nlohmann::json& a = o.json().at("axes");
  if (!a.is_array() || a.size() != 3) o.fail("axes", "must be an array of 3 unit vectors [x, y, z]");
  for (int i = 0; i < 3; ++i) {
    const nlohmann::json& v = a[size_t(i)];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      o.fail("axes", "element " + std::to_string(i) + " must be an array of 3 numbers");
    glm::vec3 d(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
    const float len = glm::length(d);
    if (!std::isfinite(len) || len < 1e-6f) o.fail("axes", "element " + std::to_string(i) + " must be non-zero");
    axes[i] = d / len;
  }
  for (int i = 0; i < 3; ++i)
    if (std::abs(glm::dot(axes[i], axes[(i + 1) % 3])) > 1e-3f) o.fail("axes", "must be mutually orthogonal");
}

FogVolume parse_volume(const JsonObject& o) {
  o.allow_only({"center", "size", "rotation_deg", "axes", "mean_free_path", "albedo", "fade", "blend", "noise"});
  FogVolume v;
  v.center = o.vec3("center", kAnyFinite);
  v.half_size = 0.5f * to_vec3(o.vec3("size", kNonNegative));
  if (o.has("rotation_deg") && o.has("axes")) o.fail("axes", "conflicts with rotation_deg (give one)");
  if (o.has("rotation_deg")) axes_from_euler(o.vec3("rotation_deg", {-3600.0, 3600.0}), v.axes);
  if (o.has("axes")) parse_axes(o, v.axes);
  v.extinction = float(1.0 / o.number("mean_free_path", kMeanFreePath));
  if (o.has("albedo")) v.albedo = to_vec3(o.vec3("albedo", kUnit));
  if (o.has("fade")) v.fade = float(o.number("fade", kNonNegative));
  if (o.has("blend")) v.blend = parse_blend(o, "blend");
  if (o.has("noise")) v.noise = parse_noise(o.object("noise"));
  return v;
}

}  // namespace

FogProfileSettings parse_fog_profile(const nlohmann::json& section, const std::string& file) {
  FogProfileSettings s;
  const JsonObject o(section, file, "fog");
  o.allow_only({"froxel_size_px", "slices", "fog_distance", "slice_uniformity", "density_samples",
                "history_weight", "filter", "jitter", "reprojection", "history_clamp",
                "light_change_rejection", "still_accumulation", "still_settled", "precision"});
  if (o.has("froxel_size_px")) s.froxel_size_px = o.integer("froxel_size_px", 1, 256);
  if (o.has("slices")) s.slices = o.integer("slices", 1, 1024);
  if (o.has("fog_distance")) s.fog_distance = float(o.number("fog_distance", {0.01, 1e7}));
  if (o.has("slice_uniformity")) s.slice_uniformity = float(o.number("slice_uniformity", kUnit));
  if (o.has("density_samples")) s.density_samples = o.integer("density_samples", 1, 64);
  if (o.has("history_weight")) s.history_weight = float(o.number("history_weight", {0.0, 1.0, false, true}));
  if (o.has("filter")) s.filter = o.boolean("filter");
  if (o.has("jitter")) s.jitter = o.boolean("jitter");
  if (o.has("reprojection")) s.reprojection = o.boolean("reprojection");
  if (o.has("history_clamp")) s.history_clamp = o.boolean("history_clamp");
  if (o.has("light_change_rejection")) s.light_change_rejection = o.boolean("light_change_rejection");
  if (o.has("still_accumulation")) s.still_accumulation = o.boolean("still_accumulation");
  if (o.has("still_settled")) s.still_settled = o.boolean("still_settled");
  if (o.has("precision")) {
    const std::string p = o.string("precision");
    if (p == "float") s.precision = FogPrecision::Float;
    else if (p == "fixed") s.precision = FogPrecision::Fixed;
    else o.fail("precision", "must be \"float\" or \"fixed\", found \"" + p + "\"");
  }
  return s;
}

FogSceneSettings parse_fog_scene(const nlohmann::json& section, const std::string& file) {
  FogSceneSettings s;
  const JsonObject o(section, file, "fog");
  o.allow_only({"height_fog", "volumes", "phase", "anisotropy", "distance"});
  if (o.has("height_fog")) {
    const JsonObject h = o.object("height_fog");
    h.allow_only({"base_height", "max_height", "mean_free_path", "albedo"});
    s.height_fog = true;
    if (h.has("base_height")) s.base_height = float(h.number("base_height", kAnyFinite));
    if (h.has("max_height")) s.max_height = float(h.number("max_height", kAnyFinite));
    if (s.max_height <= s.base_height) h.fail("max_height", "must be greater than base_height");
    s.extinction = float(1.0 / h.number("mean_free_path", kMeanFreePath));
    if (h.has("albedo")) s.albedo = to_vec3(h.vec3("albedo", kUnit));
  }
  if (o.has("volumes")) {
    const nlohmann::json& list = o.json().at("volumes");
    if (!(list.is_array() && list.empty()))  // [] means no volumes
      for (const JsonObject& v : o.objects("volumes")) s.volumes.push_back(parse_volume(v));
  }
  if (o.has("phase")) {
    const std::string p = o.string("phase");
    if (p == "hg") s.phase = FogPhase::HenyeyGreenstein;
    else if (p == "cornette-shanks") s.phase = FogPhase::CornetteShanks;
    else o.fail("phase", "must be \"hg\" or \"cornette-shanks\", found \"" + p + "\"");
  }
  if (o.has("anisotropy")) s.anisotropy = float(o.number("anisotropy", kAnisotropy));
  if (o.has("distance")) s.distance = float(o.number("distance", {0.01, 1e7}));
  return s;
}

FogProfileSettings resolve_fog_settings(const FogProfileSettings& profile, const FogSceneSettings& scene) {
  FogProfileSettings p = profile;
  if (scene.distance > 0.0f) p.fog_distance = scene.distance;
  return p;
}

}  // namespace cr
