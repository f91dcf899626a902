#include "scenes/generator/textures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include "scenes/generator/noise.h"

namespace cr::gen {

namespace {

using Texel = glm::dvec4;  // RGBA in [0, 1]

template <typename Shader>
ImageRGBA8 make_image(const std::string& name, int width, int height, Shader shade) {
  ImageRGBA8 image{name, width, height, std::vector<uint8_t>(size_t(width) * height * 4)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Texel t = shade(x, y);
      uint8_t* out = &image.rgba[(size_t(y) * width + x) * 4];
      for (int c = 0; c < 4; ++c) out[c] = static_cast<uint8_t>(std::lround(std::clamp(t[c], 0.0, 1.0) * 255.0));
    }
  }
  return image;
}

glm::dvec3 srgb8(int r, int g, int b) { return glm::dvec3(r, g, b) / 255.0; }

glm::dvec3 mix(const glm::dvec3& a, const glm::dvec3& b, double t) { return a + (b - a) * t; }

// Ground: where rock and dirt lie, in tile coordinates [0, 1).
double rock_mask(double u, double v) { return smoothstep(0.69, 0.72, fbm(u * 4.0, v * 4.0, 5u, 5, 0.5, 4)); }
double dirt_mask(double u, double v) { return smoothstep(0.64, 0.70, fbm(u * 4.0, v * 4.0, 5u, 5, 0.5, 4)); }

constexpr int kGroundSize = 256;

// Facade bay layout in pixels of a 256 x 256 image (64 px per metre across,
// 80 px per metre up).
constexpr int kFacadeSize = 256;
struct Rect {
  int x0, y0, x1, y1;
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};
constexpr Rect kWindowOuter{80, 56, 176, 184};
constexpr Rect kWindowGlassLeft{88, 64, 125, 176};
constexpr Rect kWindowGlassRight{131, 64, 168, 176};
constexpr Rect kSill{72, 184, 184, 196};

enum class FacadePart { Plaster, Frame, Glass, Sill };

FacadePart facade_part(int x, int y) {
  if (kWindowGlassLeft.contains(x, y) || kWindowGlassRight.contains(x, y)) return FacadePart::Glass;
  if (kWindowOuter.contains(x, y)) return FacadePart::Frame;
  if (kSill.contains(x, y)) return FacadePart::Sill;
  return FacadePart::Plaster;
}

// Relief of the facade in metres: the window sits 8 cm deep, the sill stands out.
double facade_height(int x, int y) {
  x = (x % kFacadeSize + kFacadeSize) % kFacadeSize;
  y = (y % kFacadeSize + kFacadeSize) % kFacadeSize;
  const double plaster = 0.004 * fbm(x / 16.0, y / 16.0, 13u, 3, 0.5, kFacadeSize / 16);
  switch (facade_part(x, y)) {
    case FacadePart::Glass: return -0.08;
    case FacadePart::Frame: return -0.03;
    case FacadePart::Sill: return 0.03;
    case FacadePart::Plaster: break;
  }
  return plaster;
}

// 5x7 bitmap glyphs for the sign's lettering, one string per row.
struct Glyph {
  char c;
  std::array<std::string_view, 7> rows;
};
constexpr std::array<Glyph, 7> kGlyphs{{
    {'C', {".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."}},
    {'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
    {'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
    {'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
    {'N', {"#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#", "#...#"}},
    {'D', {"####.", "#...#", "#...#", "#...#", "#...#", "#...#", "####."}},
}};

bool glyph_pixel(char c, int gx, int gy) {
  for (const Glyph& g : kGlyphs)
    if (g.c == c) return g.rows[size_t(gy)][size_t(gx)] == '#';
  return false;
}

}  // namespace

ImageRGBA8 ground_base_color() {
  const glm::dvec3 grass = srgb8(84, 110, 44), dry_grass = srgb8(122, 120, 58);
  const glm::dvec3 dirt = srgb8(100, 84, 60), rock = srgb8(124, 118, 106);
  return make_image("ground_base_color", kGroundSize, kGroundSize, [&](int x, int y) {
    const double u = x / double(kGroundSize), v = y / double(kGroundSize);
    const double tuft = fbm(u * 32.0, v * 32.0, 3u, 3, 0.5, 32);
    const double blade = hash_unit(x, y, 4u);
    glm::dvec3 c = mix(grass, dry_grass, smoothstep(0.45, 0.75, fbm(u * 4.0, v * 4.0, 2u, 4, 0.5, 4)));
    c *= 0.75 + 0.35 * tuft + 0.15 * (blade - 0.5);
    c = mix(c, dirt * (0.85 + 0.3 * tuft), dirt_mask(u, v));
    // Rock: mottled, with dark cracks along a lattice-noise iso-line.
    const double mottle = fbm(u * 16.0, v * 16.0, 6u, 4, 0.5, 16);
    const double crack = 1.0 - 0.55 * (1.0 - smoothstep(0.0, 0.035, std::abs(value_noise(u * 12.0, v * 12.0, 8u, 12) - 0.5)));
    c = mix(c, rock * (0.7 + 0.6 * mottle) * crack, rock_mask(u, v));
    return Texel(c, 1.0);
  });
}

ImageRGBA8 ground_metallic_roughness() {
  return make_image("ground_metallic_roughness", kGroundSize, kGroundSize, [](int x, int y) {
    const double u = x / double(kGroundSize), v = y / double(kGroundSize);
    const double grass = 0.88 + 0.1 * hash_unit(x, y, 9u);
    const double rock = 0.55 + 0.25 * fbm(u * 16.0, v * 16.0, 6u, 3, 0.5, 16);
    return Texel(1.0, grass + (rock - grass) * rock_mask(u, v), 0.0, 1.0);
  });
}

ImageRGBA8 facade_base_color() {
  const glm::dvec3 plaster = srgb8(208, 192, 164), frame = srgb8(232, 232, 226);
  const glm::dvec3 glass = srgb8(42, 56, 70), sill = srgb8(168, 162, 150);
  return make_image("facade_base_color", kFacadeSize, kFacadeSize, [&](int x, int y) {
    const double stain = fbm(x / 32.0, y / 32.0, 12u, 4, 0.5, kFacadeSize / 32);
    switch (facade_part(x, y)) {
      case FacadePart::Glass: {
        // A soft sky reflection brightening towards the top of each pane.
        const double sky = 1.0 - (y - kWindowGlassLeft.y0) / double(kWindowGlassLeft.y1 - kWindowGlassLeft.y0);
        return Texel(mix(glass, srgb8(90, 110, 130), 0.5 * sky), 1.0);
      }
      case FacadePart::Frame: return Texel(frame * (0.95 + 0.05 * stain), 1.0);
      case FacadePart::Sill: return Texel(sill * (0.85 + 0.2 * stain), 1.0);
      case FacadePart::Plaster: break;
    }
    // Plaster darkens with grime towards the bottom of each storey.
    const double grime = 0.06 * smoothstep(150.0, 256.0, y);
    return Texel(plaster * (0.82 + 0.22 * stain - grime + 0.04 * (hash_unit(x, y, 14u) - 0.5)), 1.0);
  });
}

ImageRGBA8 facade_normal() {
  constexpr double kMetresPerPixelX = 4.0 / kFacadeSize, kMetresPerPixelY = 3.2 / kFacadeSize;
  return make_image("facade_normal", kFacadeSize, kFacadeSize, [&](int x, int y) {
    // Central differences of the relief; image y grows downwards while the
    // tangent-space +Y points up the image, hence the sign of dy.
    const double dhdx = (facade_height(x + 1, y) - facade_height(x - 1, y)) / (2.0 * kMetresPerPixelX);
    const double dhdy = (facade_height(x, y + 1) - facade_height(x, y - 1)) / (2.0 * kMetresPerPixelY);
    const glm::dvec3 n = glm::normalize(glm::dvec3(-dhdx, dhdy, 1.0));
    return Texel(n * 0.5 + 0.5, 1.0);
  });
}

ImageRGBA8 facade_metallic_roughness() {
  return make_image("facade_metallic_roughness", kFacadeSize, kFacadeSize, [](int x, int y) {
    switch (facade_part(x, y)) {
      case FacadePart::Glass: return Texel(1.0, 0.08, 0.0, 1.0);
      case FacadePart::Frame: return Texel(1.0, 0.45, 0.0, 1.0);
      case FacadePart::Sill: return Texel(1.0, 0.7, 0.0, 1.0);
      case FacadePart::Plaster: break;
    }
    return Texel(1.0, 0.85 + 0.1 * hash_unit(x, y, 15u), 0.0, 1.0);
  });
}

ImageRGBA8 fence_base_color() {
  constexpr int kSize = 128;
  constexpr double kPitch = kSize / 3.0;  // three pickets per repeat
  constexpr double kPicketWidth = 26.0, kTop = 4.0, kPoint = 12.0;
  const glm::dvec3 paint = srgb8(226, 222, 208), wood = srgb8(150, 128, 98);
  return make_image("fence_base_color", kSize, kSize, [&](int x, int y) {
    const double px = std::fmod(x + 0.5, kPitch) - (kPitch - kPicketWidth) / 2.0;  // inside the picket
    const bool rail = (y >= 40 && y < 52) || (y >= 96 && y < 108);
    const double half = kPicketWidth / 2.0;
    const double tip = kTop + kPoint * std::abs(px - half) / half;  // pointed top
    const bool picket = px >= 0.0 && px < kPicketWidth && y >= tip;
    if (!picket && !rail) return Texel(0.0, 0.0, 0.0, 0.0);
    // Paint worn down to the wood along the grain.
    const double grain = value_noise(x / 3.0, y / 24.0, 21u, 0);
    const double wear = smoothstep(0.62, 0.8, fbm(x / 16.0, y / 16.0, 22u, 3, 0.5, 8));
    return Texel(mix(paint * (0.9 + 0.1 * grain), wood, wear), 1.0);
  });
}

ImageRGBA8 foliage_base_color() {
  constexpr int kSize = 128;
  const glm::dvec3 leaf = srgb8(52, 84, 34), bark = srgb8(78, 60, 44);
  // The crown: 14 overlapping blobs scattered around its centre.
  struct Blob { double x, y, r; };
  std::array<Blob, 14> blobs{};
  for (int i = 0; i < 14; ++i) {
    blobs[size_t(i)] = {64.0 + 44.0 * (hash_unit(i, 0, 31u) - 0.5), 54.0 + 44.0 * (hash_unit(i, 1, 31u) - 0.5),
                        14.0 + 12.0 * hash_unit(i, 2, 31u)};
  }
  return make_image("foliage_base_color", kSize, kSize, [&](int x, int y) {
    const double cx = x + 0.5, cy = y + 0.5;
    double depth = 0.0;  // how far inside the crown, in blob radii
    for (const Blob& b : blobs) {
      const double d = std::sqrt((cx - b.x) * (cx - b.x) + (cy - b.y) * (cy - b.y));
      depth = std::max(depth, 1.0 - d / b.r);
    }
    const double leaves = value_noise(x / 3.0, y / 3.0, 32u);
    if (depth > 0.0 && leaves > 0.45 - 0.5 * depth) {
      const double shade = 0.6 + 0.5 * depth + 0.3 * (leaves - 0.5);
      return Texel(mix(leaf, srgb8(96, 120, 44), hash_unit(x / 4, y / 4, 33u) * 0.5) * shade, 1.0);
    }
    const double trunk_half_width = 3.0 + 4.0 * smoothstep(90.0, 128.0, cy);
    if (std::abs(cx - 64.0) < trunk_half_width && cy > 70.0) {
      return Texel(bark * (0.8 + 0.3 * value_noise(x / 2.0, y / 10.0, 34u)), 1.0);
    }
    return Texel(0.0, 0.0, 0.0, 0.0);
  });
}

ImageRGBA8 sign_emissive() {
  constexpr int kWidth = 128, kHeight = 32, kScale = 2;
  constexpr std::string_view kText = "CPURENDER";
  constexpr int kTextX = (kWidth - int(kText.size()) * 6 * kScale + kScale) / 2, kTextY = (kHeight - 7 * kScale) / 2;
  const glm::dvec3 light = srgb8(255, 196, 120);
  return make_image("sign_emissive", kWidth, kHeight, [&](int x, int y) {
    const bool border = (x == 2 || x == kWidth - 3 || y == 2 || y == kHeight - 3) && x >= 2 && x <= kWidth - 3 &&
                        y >= 2 && y <= kHeight - 3;
    const int tx = (x - kTextX) / kScale, ty = (y - kTextY) / kScale;
    bool letter = false;
    if (x >= kTextX && y >= kTextY && ty < 7 && tx / 6 < int(kText.size()) && tx % 6 < 5) {
      letter = glyph_pixel(kText[size_t(tx / 6)], tx % 6, ty);
    }
    return Texel(letter || border ? light : glm::dvec3(0.0), 1.0);
  });
}

glm::vec3 mean_linear_color(const ImageRGBA8& image) {
  std::array<double, 256> linear{};
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    linear[size_t(i)] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  }
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < image.rgba.size(); i += 4)
    sum += glm::dvec3(linear[image.rgba[i]], linear[image.rgba[i + 1]], linear[image.rgba[i + 2]]);
  return glm::vec3(sum / double(size_t(image.width) * image.height));
}

}  // namespace cr::gen
