#include "engine/scene/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "engine/scene/image_mips.h"

namespace cr {

namespace {

Wrap convert_wrap(const GltfContext& ctx, int mode, const std::string& what) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return Wrap::Repeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Wrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Wrap::MirroredRepeat;
    default: ctx.fail(what + " has invalid value " + std::to_string(mode));
  }
}

Sampler convert_sampler(const GltfContext& ctx, const tinygltf::Sampler& s, size_t index) {
  std::string label = gltf_label("sampler", index, s.name);
  Sampler out;
  out.wrap_s = convert_wrap(ctx, s.wrapS, label + " wrapS");
  out.wrap_t = convert_wrap(ctx, s.wrapT, label + " wrapT");
  switch (s.magFilter) {
    case -1:  // undefined: the renderer's choice
    case TINYGLTF_TEXTURE_FILTER_LINEAR: out.mag = Filter::Linear; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST: out.mag = Filter::Nearest; break;
    default: ctx.fail(label + " magFilter has invalid value " + std::to_string(s.magFilter));
  }
  switch (s.minFilter) {
    case -1:  // undefined: trilinear, the best quality on offer
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR: out.min = Filter::Linear; out.mip = Filter::Linear; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST: out.min = Filter::Nearest; out.mip.reset(); break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR: out.min = Filter::Linear; out.mip.reset(); break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: out.min = Filter::Nearest; out.mip = Filter::Nearest; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: out.min = Filter::Linear; out.mip = Filter::Nearest; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: out.min = Filter::Nearest; out.mip = Filter::Linear; break;
    default: ctx.fail(label + " minFilter has invalid value " + std::to_string(s.minFilter));
  }
  return out;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

// A number that stays finite as a float.
float finite_float(const GltfContext& ctx, const tinygltf::Value& v, const std::string& what) {
  if (!v.IsNumber()) ctx.fail(what + " must be a number");
  const double d = v.GetNumberAsDouble();
  if (!std::isfinite(static_cast<float>(d))) ctx.fail(what + " is " + std::to_string(d) + "; must be finite");
  return static_cast<float>(d);
}

glm::vec2 finite_vec2(const GltfContext& ctx, const tinygltf::Value& v, const std::string& what) {
  if (!v.IsArray() || v.ArrayLen() != 2) ctx.fail(what + " must be an array of 2 numbers");
  return {finite_float(ctx, v.Get(0), what + "[0]"), finite_float(ctx, v.Get(1), what + "[1]")};
}

// KHR_texture_transform of a texture reference (identity without it);
// `texcoord` takes its texCoord override.
UvTransform texture_transform(const GltfContext& ctx, const tinygltf::ExtensionMap& extensions, int& texcoord,
                              const std::string& what) {
  UvTransform t;
  auto ext = extensions.find("KHR_texture_transform");
  if (ext == extensions.end()) return t;
  const tinygltf::Value& v = ext->second;
  const std::string label = what + " KHR_texture_transform";
  if (v.Has("offset")) t.offset = finite_vec2(ctx, v.Get("offset"), label + " offset");
  if (v.Has("rotation")) t.rotation = finite_float(ctx, v.Get("rotation"), label + " rotation");
  if (v.Has("scale")) t.scale = finite_vec2(ctx, v.Get("scale"), label + " scale");
  if (v.Has("texCoord")) {
    const tinygltf::Value& set = v.Get("texCoord");
    if (!set.IsNumber() || set.GetNumberAsDouble() != std::floor(set.GetNumberAsDouble()) ||
        std::abs(set.GetNumberAsDouble()) > 1e9)
      ctx.fail(label + " texCoord must be an integer");
    texcoord = static_cast<int>(set.GetNumberAsDouble());
  }
  return t;
}

// Resolves material texture references to scene images, creating each
// (glTF image, colour space) pair once, and collects unusable images.
class TextureResolver {
 public:
  TextureResolver(const GltfContext& ctx, const ImageDecodeLog& log) : ctx_(ctx), log_(log) {}

  // A texture reference: its texture, UV set (texCoord, or its
  // KHR_texture_transform override) and transform. Sets 0 and 1 are read;
  // a higher set falls back to TEXCOORD_0 with a warning.
  TextureRef resolve(int texture, int texcoord, const tinygltf::ExtensionMap& extensions, float scale, bool srgb,
                     const std::string& what) {
    TextureRef ref;
    ref.scale = scale;
    if (texture == -1) return ref;
    const tinygltf::Model& m = ctx_.model;
    if (texture < 0 || static_cast<size_t>(texture) >= m.textures.size()) {
      ctx_.fail(what + ": texture index " + std::to_string(texture) + " out of range (" +
                std::to_string(m.textures.size()) + " textures)");
    }
    const UvTransform transform = texture_transform(ctx_, extensions, texcoord, what);
    if (texcoord < 0) ctx_.fail(what + ": texCoord " + std::to_string(texcoord) + " is negative");
    if (texcoord > 1) {
      ctx_.warn(what + " uses TEXCOORD_" + std::to_string(texcoord) +
                "; only TEXCOORD_0 and TEXCOORD_1 are supported, so TEXCOORD_0 is used instead");
      texcoord = 0;
    }
    const tinygltf::Texture& t = m.textures[texture];
    std::string tlabel = what + ": " + gltf_label("texture", texture, t.name);
    if (t.source < 0 || static_cast<size_t>(t.source) >= m.images.size()) {
      ctx_.fail(tlabel + " has image source " + std::to_string(t.source) + " out of range (" +
                std::to_string(m.images.size()) + " images); images supplied by extensions are not supported");
    }
    if (t.sampler < -1 || (t.sampler >= 0 && static_cast<size_t>(t.sampler) >= m.samplers.size())) {
      ctx_.fail(tlabel + " has sampler " + std::to_string(t.sampler) + " out of range (" +
                std::to_string(m.samplers.size()) + " samplers)");
    }
    const tinygltf::Image& img = m.images[t.source];
    std::string ilabel = gltf_label("image", t.source, img.name) + (img.uri.empty() || is_data_uri(img.uri) ? "" : " '" + img.uri + "'");
    auto failed = log_.failures.find(t.source);
    if (failed != log_.failures.end()) {
      undecodable_.insert(ilabel + ": " + failed->second);
      return ref;
    }
    if (img.image.empty()) {
      if (!img.uri.empty() && !is_data_uri(img.uri)) {
        missing_.insert(img.uri);
      } else {
        undecodable_.insert(ilabel + ": no image data");
      }
      return ref;
    }
    auto key = std::make_pair(t.source, srgb);
    auto it = scene_image_.find(key);
    if (it == scene_image_.end()) {
      it = scene_image_.emplace(key, static_cast<int>(sources_.size())).first;
      sources_.push_back(key);
    }
    ref.image = it->second;
    ref.sampler = t.sampler;
    ref.texcoord = texcoord;
    ref.transform = transform;
    return ref;
  }

  const std::set<std::string>& missing() const { return missing_; }
  const std::set<std::string>& undecodable() const { return undecodable_; }
  const std::vector<std::pair<int, bool>>& sources() const { return sources_; }

 private:
  const GltfContext& ctx_;
  const ImageDecodeLog& log_;
  std::map<std::pair<int, bool>, int> scene_image_;
  std::vector<std::pair<int, bool>> sources_;  // scene image -> (glTF image, sRGB)
  std::set<std::string> missing_;
  std::set<std::string> undecodable_;
};

float factor(const GltfContext& ctx, double v, double lo, double hi, const std::string& what) {
  if (!std::isfinite(v) || v < lo || v > hi) {
    ctx.fail(what + " is " + std::to_string(v) + "; must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return static_cast<float>(v);
}

Material convert_material(const GltfContext& ctx, TextureResolver& textures, const tinygltf::Material& src,
                          size_t index) {
  std::string label = gltf_label("material", index, src.name);
  const tinygltf::PbrMetallicRoughness& pbr = src.pbrMetallicRoughness;
  Material m;
  m.name = src.name;
  // baseColorFactor has 4 components and emissiveFactor 3 (validate_gltf_schema).
  for (int c = 0; c < 4; ++c) {
    m.base_color_factor[c] = factor(ctx, pbr.baseColorFactor[c], 0.0, 1.0, label + " baseColorFactor");
  }
  m.metallic_factor = factor(ctx, pbr.metallicFactor, 0.0, 1.0, label + " metallicFactor");
  m.roughness_factor = factor(ctx, pbr.roughnessFactor, 0.0, 1.0, label + " roughnessFactor");
  for (int c = 0; c < 3; ++c) {
    m.emissive_factor[c] = factor(ctx, src.emissiveFactor[c], 0.0, 1.0, label + " emissiveFactor");
  }
  if (auto ext = src.extensions.find("KHR_materials_emissive_strength"); ext != src.extensions.end()) {
    const std::string what = label + " KHR_materials_emissive_strength emissiveStrength";
    if (ext->second.Has("emissiveStrength")) {
      m.emissive_strength = finite_float(ctx, ext->second.Get("emissiveStrength"), what);
      if (m.emissive_strength < 0.0f) ctx.fail(what + " is " + std::to_string(m.emissive_strength) + "; must be >= 0");
    }
  }
  m.unlit = src.extensions.count("KHR_materials_unlit") > 0;
  m.base_color = textures.resolve(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                  pbr.baseColorTexture.extensions, 1.0f, true, label + " baseColorTexture");
  m.metallic_roughness =
      textures.resolve(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                       pbr.metallicRoughnessTexture.extensions, 1.0f, false, label + " metallicRoughnessTexture");
  float normal_scale = factor(ctx, src.normalTexture.scale, -1e6, 1e6, label + " normalTexture.scale");
  m.normal = textures.resolve(src.normalTexture.index, src.normalTexture.texCoord, src.normalTexture.extensions,
                              normal_scale, false, label + " normalTexture");
  float strength = factor(ctx, src.occlusionTexture.strength, 0.0, 1.0, label + " occlusionTexture.strength");
  m.occlusion = textures.resolve(src.occlusionTexture.index, src.occlusionTexture.texCoord,
                                 src.occlusionTexture.extensions, strength, false, label + " occlusionTexture");
  m.emissive = textures.resolve(src.emissiveTexture.index, src.emissiveTexture.texCoord,
                                src.emissiveTexture.extensions, 1.0f, true, label + " emissiveTexture");
  if (src.alphaMode == "OPAQUE") {
    m.alpha_mode = AlphaMode::Opaque;
  } else if (src.alphaMode == "MASK") {
    m.alpha_mode = AlphaMode::Mask;
  } else if (src.alphaMode == "BLEND") {
    m.alpha_mode = AlphaMode::Blend;
  } else {
    ctx.fail(label + " alphaMode \"" + src.alphaMode + "\" is not OPAQUE, MASK or BLEND");
  }
  m.alpha_cutoff = factor(ctx, src.alphaCutoff, 0.0, 1e6, label + " alphaCutoff");
  m.double_sided = src.doubleSided;
  return m;
}

// Texels of an image's mip chain, down to 1x1 as generate_mips builds it.
size_t mip_chain_texels(size_t width, size_t height) {
  size_t texels = width * height;
  while (width > 1 || height > 1) {
    width = std::max<size_t>(1, width / 2);
    height = std::max<size_t>(1, height / 2);
    texels += width * height;
  }
  return texels;
}

// Size of level `level` of a chain with the given base size.
size_t level_size(size_t base, int level) { return std::max<size_t>(1, base >> level); }

// An image's place under the texture budget: its file size and the top
// levels of its chain it drops.
struct BudgetedImage {
  size_t width, height;
  int drop = 0;
  size_t width_kept() const { return level_size(width, drop); }
  size_t height_kept() const { return level_size(height, drop); }
  size_t bytes() const { return 4 * mip_chain_texels(width_kept(), height_kept()); }
  bool droppable() const { return width_kept() > 1 || height_kept() > 1; }
};

// Drops top levels until the chains fit `budget`: each step takes the
// largest chain (the earlier image on ties) one level down, so the largest
// images shrink first and images of one size end up within a level of each
// other, as a GPU texture pool's mip bias does. Stops at 1x1 levels.
void fit_texture_budget(std::vector<BudgetedImage>& images, size_t budget) {
  size_t total = 0;
  for (const BudgetedImage& b : images) total += b.bytes();
  while (total > budget) {
    BudgetedImage* largest = nullptr;
    for (BudgetedImage& b : images)
      if (b.droppable() && (!largest || b.bytes() > largest->bytes())) largest = &b;
    if (!largest) return;
    total -= largest->bytes();
    ++largest->drop;
    total += largest->bytes();
  }
}

std::string join(const std::set<std::string>& items, const std::string& sep) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : sep) + s;
  return out;
}

}  // namespace

GltfMaterials load_materials(const GltfContext& ctx, const ImageDecodeLog& decode_log,
                             const GltfLoadOptions& options) {
  const tinygltf::Model& m = ctx.model;
  GltfMaterials out;
  for (size_t i = 0; i < m.samplers.size(); ++i) out.samplers.push_back(convert_sampler(ctx, m.samplers[i], i));

  for (size_t i = 0; i < m.textures.size(); ++i) {
    const tinygltf::Texture& t = m.textures[i];
    std::string label = gltf_label("texture", i, t.name);
    if (t.source < -1 || (t.source >= 0 && static_cast<size_t>(t.source) >= m.images.size())) {
      ctx.fail(label + " source " + std::to_string(t.source) + " out of range (" + std::to_string(m.images.size()) + " images)");
    }
    if (t.sampler < -1 || (t.sampler >= 0 && static_cast<size_t>(t.sampler) >= m.samplers.size())) {
      ctx.fail(label + " sampler " + std::to_string(t.sampler) + " out of range (" + std::to_string(m.samplers.size()) + " samplers)");
    }
  }

  TextureResolver textures(ctx, decode_log);
  for (size_t i = 0; i < m.materials.size(); ++i) {
    out.materials.push_back(convert_material(ctx, textures, m.materials[i], i));
  }
  if (!textures.undecodable().empty()) {
    ctx.fail("cannot decode " + std::to_string(textures.undecodable().size()) + " image(s): " +
             join(textures.undecodable(), "; "));
  }
  if (!textures.missing().empty()) {
    std::string list = join(textures.missing(), ", ");
    if (!options.allow_missing_images) {
      ctx.fail(std::to_string(textures.missing().size()) + " image file(s) missing: " + list +
               " (pass --allow-missing-images to render with the material factors instead)");
    }
    ctx.warn(std::to_string(textures.missing().size()) + " image file(s) missing, textures using them are dropped "
             "and their materials use their factors: " + list);
  }

  // What each image will take, from its header's size (capture_gltf_image
  // bounds it): RGBA8 with its mips, top levels dropped where the images
  // exceed the texture budget; charged, with the peak of decoding each one
  // checked, before any is decoded.
  std::vector<BudgetedImage> budgeted;
  for (const std::pair<int, bool>& used : textures.sources()) {
    const tinygltf::Image& img = m.images[used.first];
    budgeted.push_back({static_cast<size_t>(img.width), static_cast<size_t>(img.height)});
  }
  fit_texture_budget(budgeted, options.texture_decode_budget);
  std::string dropped;
  size_t full_bytes = 0, kept_bytes = 0;
  for (size_t i = 0; i < budgeted.size(); ++i) {
    const int source = textures.sources()[i].first;
    const tinygltf::Image& img = m.images[source];
    const BudgetedImage& b = budgeted[i];
    const std::string size = std::to_string(img.width) + "x" + std::to_string(img.height);
    const std::string kept = std::to_string(b.width_kept()) + "x" + std::to_string(b.height_kept());
    full_bytes += BudgetedImage{b.width, b.height}.bytes();
    kept_bytes += b.bytes();
    if (b.drop > 0) {
      dropped += std::string(dropped.empty() ? "" : "; ") + gltf_label("image", source, img.name) +
                 (textures.sources()[i].second ? " (sRGB)" : " (linear)") + " loads at " + kept + " (of " + size +
                 ")";
    }
    if (options.memory) {
      const std::string what = gltf_label("image", source, img.name) + " (" + size +
                               (b.drop > 0 ? " loaded at " + kept : "") + " RGBA8 with mips)";
      const std::string field = "images[" + std::to_string(source) + "]";
      options.memory->charge(what, ctx.path, field, b.bytes());
      // Decoding holds the file's full level and the next one made from it.
      if (b.drop > 0) {
        options.memory->require(what + " while decoding", ctx.path, field,
                                4 * (b.width * b.height + level_size(b.width, 1) * level_size(b.height, 1)));
      }
    }
  }
  if (!dropped.empty()) {
    ctx.warn("the images' mip chains (" + MemoryBudget::format_bytes(full_bytes) +
             " as RGBA8) exceed the texture budget (texture_decode_budget_mb, " +
             MemoryBudget::format_bytes(options.texture_decode_budget) + "): " + dropped + "; " +
             MemoryBudget::format_bytes(kept_bytes) + " kept");
  }
  for (size_t i = 0; i < textures.sources().size(); ++i) {
    const auto& [source, srgb] = textures.sources()[i];
    const tinygltf::Image& img = m.images[source];
    Image image;
    image.name = !img.name.empty() ? img.name : (is_data_uri(img.uri) ? "image " + std::to_string(source) : img.uri);
    image.srgb = srgb;
    MipLevel base;
    std::string error;
    if (!decode_gltf_image(img, source, base, error)) {
      ctx.fail(gltf_label("image", source, img.name) +
               (img.uri.empty() || is_data_uri(img.uri) ? "" : " '" + img.uri + "'") + ": " + error);
    }
    image.mips.push_back(std::move(base));
    generate_mips(image, budgeted[i].drop);
    out.images.push_back(std::move(image));
  }
  return out;
}

}  // namespace cr
