#include "engine/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <limits>

#include "engine/core/error.h"
#include "engine/raster/blend_order.h"
#include "engine/raster/tiled_rasterizer.h"
#include "engine/render/composite_strips.h"
#include "engine/render/display_transform.h"
#include "engine/render/edge_fragments.h"
#include "engine/render/frame_view.h"
#include "engine/render/view_distance.h"
#include "engine/shading/material_batch.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/sh_lighting.h"
#include "engine/shading/shade_surface.h"
#include "engine/shading/surface.h"
#include "engine/shading/surface_batch.h"

namespace cr {

namespace {

const Material& material_of(const Scene& scene, const Primitive& prim) {
  static const Material kDefault;  // glTF default material: white, metallic 1, roughness 1
  return prim.material >= 0 ? scene.materials[prim.material] : kDefault;
}

// Camera-relative model -> clip, composed in double so a large camera offset
// does not cost float precision (the float matrix only holds small numbers).
glm::mat4 model_to_clip(const glm::mat4& view_proj, const glm::dvec3& origin, const glm::mat4& world) {
  glm::dmat4 w(world);
  w[3] -= glm::dvec4(origin, 0.0);
  return glm::mat4(glm::dmat4(view_proj) * w);
}

// Conservative test of a world AABB against the camera frustum (infinite far),
// or an orthographic camera's box.
bool aabb_in_view(const Camera& cam, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 c = 0.5f * (lo + hi) - glm::vec3(cam.position);
  const glm::vec3 e = 0.5f * (hi - lo);
  if (cam.orthographic) {
    // Inward normals and the planes' distances from the camera.
    const float hh = cam.ortho_half_height, hw = hh * cam.aspect;
    const glm::vec3 normals[6] = {cam.right, -cam.right, cam.up, -cam.up, cam.forward, -cam.forward};
    const float offsets[6] = {hw, hw, hh, hh, -cam.znear, cam.zfar};
    for (int i = 0; i < 6; ++i) {
      const glm::vec3& n = normals[i];
      const float r = e.x * std::abs(n.x) + e.y * std::abs(n.y) + e.z * std::abs(n.z);
      if (glm::dot(n, c) + r + offsets[i] < 0.0f) return false;
    }
    return true;
  }
  const float ty = std::tan(0.5f * cam.vfov_rad), tx = ty * cam.aspect;
  // Inward plane normals of the four side planes and the near plane.
  const glm::vec3 normals[5] = {
      glm::normalize(cam.forward * tx + cam.right), glm::normalize(cam.forward * tx - cam.right),
      glm::normalize(cam.forward * ty + cam.up), glm::normalize(cam.forward * ty - cam.up), cam.forward};
  for (int i = 0; i < 5; ++i) {
    const glm::vec3& n = normals[i];
    const float r = e.x * std::abs(n.x) + e.y * std::abs(n.y) + e.z * std::abs(n.z);
    const float d = glm::dot(n, c) + r - (i == 4 ? cam.znear : 0.0f);
    if (d < 0.0f) return false;
  }
  return true;
}

// Whether a world AABB overlaps the clip volume of an orthographic projection
// (x, y in [-1, 1]; z below 0 is beyond the map's depth range).
bool aabb_in_ortho(const glm::mat4& view_proj, const glm::dvec3& origin, const glm::vec3& lo, const glm::vec3& hi) {
  glm::vec3 cmin(std::numeric_limits<float>::max()), cmax(-std::numeric_limits<float>::max());
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::vec3 c(view_proj * glm::vec4(glm::vec3(corner - origin), 1.0f));
    cmin = glm::min(cmin, c);
    cmax = glm::max(cmax, c);
  }
  return cmax.x >= -1.0f && cmin.x <= 1.0f && cmax.y >= -1.0f && cmin.y <= 1.0f && cmax.z >= 0.0f;
}

// Alpha-MASK coverage of a rasterizer's triangles: base-colour alpha >= cutoff.
CoverageFn alpha_coverage(const Scene& scene, const TiledRasterizer& raster) {
  return [&scene, &raster](uint32_t id, const Barycentrics& bary) {
    const TriangleRef r = raster.ref(id);
    const Draw& d = scene.draws[r.draw_index];
    const Primitive& prim = scene.primitive(d);
    const Material& m = material_of(scene, prim);
    return material_alpha(scene, m, interpolate_uv_color(prim, r.triangle_index, bary, m.base_color.texcoord == 1)) >=
           m.alpha_cutoff;
  };
}

// Surfaces to shade, interpolated run by run (points on one triangle), then
// finished batch-wide, their materials evaluated and lit; where[k] names
// the pixel or fragment entry k belongs to.
struct ShadeQueue {
  SurfaceBatch surfaces;
  const Material* materials[SurfaceBatch::kCapacity];
  ShadingBatch batch;
  size_t where[SurfaceBatch::kCapacity];

  // Shades the queue and hands out(where[k], radiance) each point.
  template <class Out>
  void flush(const Scene& scene, float emissive_luminance, const SurfaceShader& shader, Out&& out) {
    surfaces.finish();
    evaluate_materials(scene, surfaces, materials, emissive_luminance, batch);
    shader.shade_batch(batch);
    for (int k = 0; k < batch.count; ++k) out(where[k], batch.radiance(k));
    surfaces.clear();
    batch.clear();
  }
};

}  // namespace

struct Renderer::Geometry {
  TiledRasterizer view;    // the camera's visibility buffer
  TiledRasterizer shadow;  // the sun's depth map
  std::vector<RasterDraw> opaque, blended, casters;
  RasterStats stats;
  // Multisampling: per-pixel ids (edge_pixel_id at edge pixels) and the
  // per-tile lists the edge fragments are gathered from.
  std::vector<uint32_t> pixel_ids;
  FragmentRows fragment_rows;
  bool shadow_reused = false;  // the shadow projection did not move: last map kept
};

Renderer::Renderer(const Scene& scene, const SceneDescription& description, const Profile& profile,
                   std::vector<std::unique_ptr<Plugin>> plugins, JobSystem& jobs)
    : scene_(scene), description_(description), profile_(profile), jobs_(jobs),
      geometry_(std::make_unique<Geometry>()) {
  if (description.camera.gltf_camera && *description.camera.gltf_camera >= int(scene.cameras.size()))
    throw InputError(description.path, "camera.gltf_camera is " + std::to_string(*description.camera.gltf_camera) +
                                           " but '" + scene.source + "' has " + std::to_string(scene.cameras.size()) +
                                           " perspective camera(s)");
  for (auto& p : plugins)
    if (p->configure(scene, description, profile)) plugins_.push_back(std::move(p));
  for (const auto& p : plugins_)
    if (p->provides_light_environment()) {
      if (light_provider_)
        throw InputError(description.path, "plugins '" + light_provider_->name() + "' and '" + p->name() +
                                               "' both provide the light environment; a scene may use one");
      light_provider_ = p.get();
    }
  std::stable_sort(plugins_.begin(), plugins_.end(),
                   [](const auto& a, const auto& b) { return a->composite_order() < b->composite_order(); });
  buffers_.resize(profile.width, profile.height);
}

Renderer::~Renderer() = default;

std::vector<int32_t> Renderer::pixel_draws() const {
  const VisibilityBuffer& v = geometry_->view.visibility();
  std::vector<int32_t> draws(v.triangle.size(), -1);
  for (size_t i = 0; i < draws.size(); ++i)
    if (v.triangle[i] != kNoTriangle) draws[i] = int32_t(geometry_->view.ref(v.triangle[i]).draw_index);
  return draws;
}

FrameView Renderer::frame_view(int frame) const {
  return make_frame_view(scene_, description_, frame, profile_.width, profile_.height);
}

Plugin* Renderer::plugin(const std::string& name) const {
  for (const auto& p : plugins_)
    if (p->name() == name) return p.get();
  return nullptr;
}

const FrameRecord& Renderer::render_frame(int frame) {
  if (frame <= last_frame_) throw Error("renderer: frames must be rendered in increasing order");
  PassTiming pose{"pose", jobs_.now_us(), 0.0};
  if (pose_) pose_(frame);
  pose.end_us = jobs_.now_us();
  FrameView view = frame_view(frame);
  if (frame != last_frame_ + 1) {  // skipped frames: temporal history is not valid
    view.history_valid = false;
    view.prev_camera = view.camera;
  }
  last_frame_ = frame;

  Geometry& geo = *geometry_;
  const Camera& cam = view.camera;
  const FrameContext ctx{scene_, description_, profile_, view};
  const int w = buffers_.width, h = buffers_.height;
  const int tile = profile_.tile_size;
  const bool sun_up = view.sun_direction.y > 0.0f && glm::length(view.sun_illuminance) > 0.0f;

  FrameGraph graph;
  EngineResources engine;
  engine.light = graph.create("light_environment", light_);
  engine.shadow = graph.import("shadow_map", shadow_);
  engine.previous_shadow = graph.import("previous_shadow_map", previous_shadow_);
  FrameGraphId<Geometry> visibility = graph.create("visibility", geo);
  engine.depth = graph.create("depth", buffers_);
  FrameGraphId<FrameBuffers> color = graph.create("hdr_color", buffers_);
  FrameGraphId<FrameBuffers> display = graph.create("frame", buffers_);
  using Builder = FrameGraph::Builder;
  using Resources = FrameGraph::Resources;

  struct LightData {
    FrameGraphId<LightEnvironment> light;
  };
  graph.add_pass<LightData>(
      "light", [&](Builder& b, LightData& d) { d.light = engine.light = b.write(engine.light); },
      [sun = view.sun_direction, illuminance = sun_up ? view.sun_illuminance : glm::vec3(0.0f),
       ambient = description_.ambient](const Resources& r, const LightData& d) {
        LightEnvironment& light = r.get_mutable(d.light);
        light = LightEnvironment{};
        light.sun_direction = sun;
        light.sun_illuminance = illuminance;
        light.ambient_sh = sh_constant_radiance(ambient);
      });

  const bool shadows = profile_.shadow_map_size > 0 && sun_up;
  struct ShadowData {
    FrameGraphId<ShadowMap> shadow, previous;
  };
  if (shadows)
    graph.add_pass<ShadowData>("shadow", [&](Builder& b, ShadowData& d) {
      d.shadow = engine.shadow = b.write(engine.shadow);
      d.previous = engine.previous_shadow = b.write(engine.previous_shadow);
    }, [this, &geo, &view](const Resources& r, const ShadowData& d) {
      ShadowMap& shadow = r.get_mutable(d.shadow);
      ShadowMap& previous = r.get_mutable(d.previous);
      ShadowMap fit = fit_shadow_projection(view.camera, view.sun_direction, profile_.shadow_distance,
                                     profile_.shadow_map_size, profile_.shadow_pcf_radius, scene_.bounds_min,
                                     scene_.bounds_max);
      // A still scene: when the texel-snapped projection has not moved, last
      // frame's map is exactly what a new render would produce.
      const bool unchanged = !pose_ && fit.size == shadow.size && fit.light_view_proj == shadow.light_view_proj &&
                             fit.origin == shadow.origin && fit.direction_to_sun == shadow.direction_to_sun;
      if (unchanged) {
        previous.size = 0;  // nothing to compare against (its memory is kept for the next render)
        geo.shadow_reused = true;
        return;
      }
      // Last frame's map becomes the previous one (temporal plugins compare
      // against it when the sun moves); the new map renders into the memory
      // of the one before (the render writes every texel).
      fit.depth.swap(previous.depth);
      previous = std::move(shadow);
      shadow = std::move(fit);
      geo.shadow_reused = false;
      geo.casters.clear();
      for (uint32_t i = 0; i < scene_.draws.size(); ++i) {
        const Draw& d = scene_.draws[i];
        const Material& m = material_of(scene_, scene_.primitive(d));
        if (m.alpha_mode == AlphaMode::Blend) continue;  // translucent surfaces cast no shadow
        if (!aabb_in_ortho(shadow.light_view_proj, shadow.origin, d.world_bounds_min, d.world_bounds_max)) continue;
        geo.casters.push_back({&scene_.primitive(d), model_to_clip(shadow.light_view_proj, shadow.origin, d.world),
                               true, d.mirrored, m.alpha_mode == AlphaMode::Mask, i});
      }
      geo.shadow.render_depth(r.jobs(), shadow.size, profile_.tile_size, geo.casters, shadow.depth,
                              alpha_coverage(scene_, geo.shadow));
    });
  else
    shadow_ = previous_shadow_ = ShadowMap{};

  // Draws outside the view frustum cost nothing past this test.
  geo.opaque.clear();
  geo.blended.clear();
  std::vector<glm::dvec3> blend_centres;
  const glm::mat4 view_proj = cam.view_proj();
  for (uint32_t i = 0; i < scene_.draws.size(); ++i) {
    const Draw& d = scene_.draws[i];
    if (!aabb_in_view(cam, d.world_bounds_min, d.world_bounds_max)) continue;
    const Material& m = material_of(scene_, scene_.primitive(d));
    RasterDraw rd{&scene_.primitive(d), model_to_clip(view_proj, cam.position, d.world), m.double_sided,
                  d.mirrored, m.alpha_mode == AlphaMode::Mask, i};
    if (m.alpha_mode != AlphaMode::Blend) {
      geo.opaque.push_back(rd);
      continue;
    }
    geo.blended.push_back(rd);
    blend_centres.push_back(0.5 * (glm::dvec3(d.world_bounds_min) + glm::dvec3(d.world_bounds_max)));
  }
  if (!geo.blended.empty()) {
    std::vector<RasterDraw> sorted;
    for (uint32_t i : back_to_front_order(blend_centres, cam.position, cam.forward)) sorted.push_back(geo.blended[i]);
    geo.blended.swap(sorted);
  }

  struct GeometryData {
    FrameGraphId<Geometry> visibility;
    FrameGraphId<FrameBuffers> depth;
  };
  graph.add_pass<GeometryData>("geometry", [&](Builder& b, GeometryData& d) {
    d.visibility = visibility = b.write(visibility);
    d.depth = engine.depth = b.write(engine.depth);
  }, [this, &cam, w, h, tile](const Resources& r, const GeometryData& d) {
    Geometry& geo = r.get_mutable(d.visibility);
    FrameBuffers& buffers = r.get_mutable(d.depth);
    JobSystem& jobs = r.jobs();
    geo.stats = geo.view.render_visibility(jobs, w, h, tile, geo.opaque, alpha_coverage(scene_, geo.view),
                                           profile_.msaa_samples);
    if (profile_.msaa_samples == 1) {
      buffers.depth = geo.view.visibility().depth;
      buffers.fragments.clear();
    } else {
      classify_samples(geo.view, cam, jobs, geo.pixel_ids, buffers.depth, buffers.fragments, geo.fragment_rows);
    }
    view_distances(cam, w, h, buffers.depth, buffers.distance, jobs);
  });

  // The light-environment provider declares its passes first: every other
  // plugin's passes and the shade pass read the light it writes.
  if (light_provider_) light_provider_->add_passes(graph, ctx, engine);
  for (auto& p : plugins_) {
    if (p.get() == light_provider_) continue;
    const FrameGraphHandle light = engine.light;
    p->add_passes(graph, ctx, engine);
    if (engine.light.version() != light.version())
      throw Error("plugin '" + p->name() + "' writes the light environment but does not provide it");
  }

  // An orthographic view's rays are parallel: shading takes its view vectors
  // from a point 10^7 m back along them, whose directions differ from -forward
  // by less than the scene's extent / 10^7 radians.
  const glm::dvec3 eye = cam.orthographic ? cam.position - glm::dvec3(cam.forward) * 1e7 : cam.position;
  const float emissive = emissive_luminance(description_);
  // The shader of a pass that shades, from the light and shadow it reads.
  auto shader_of = [this, eye, emissive](const Resources& r, FrameGraphId<LightEnvironment> light,
                                         FrameGraphId<ShadowMap> shadow) {
    return SurfaceShader(ShadingInputs{&scene_, &r.get(light), &r.get(shadow), eye, emissive});
  };
  // TEXCOORD_1 is interpolated for materials reading it; most scenes have none.
  const bool any_uv1 =
      std::any_of(scene_.materials.begin(), scene_.materials.end(), [](const Material& m) { return needs_uv1(m); });
  // The triangle a visibility-buffer id names, in world space, and its material.
  auto triangle_of = [this, any_uv1](const Geometry& geo, uint32_t id, const Material*& material) {
    const TriangleRef r = geo.view.ref(id);
    const Draw& d = scene_.draws[r.draw_index];
    const Primitive& prim = scene_.primitive(d);
    material = &material_of(scene_, prim);
    return TriangleSurface(prim, d, r.triangle_index, r.front_facing, needs_tangent(*material),
                           any_uv1 && needs_uv1(*material));
  };

  struct ShadeData {
    FrameGraphId<Geometry> visibility;
    FrameGraphId<ShadowMap> shadow;
    FrameGraphId<LightEnvironment> light;
    FrameGraphId<FrameBuffers> color;
  };
  graph.add_pass<ShadeData>("shade", [&](Builder& b, ShadeData& d) {
    d.visibility = b.read(visibility);
    d.shadow = b.read(engine.shadow);
    d.light = b.read(engine.light);
    d.color = color = b.write(color);
  }, [this, &triangle_of, &shader_of, emissive, w, h](const Resources& r, const ShadeData& d) {
    const Geometry& geo = r.get(d.visibility);
    FrameBuffers& buffers = r.get_mutable(d.color);
    JobSystem& jobs = r.jobs();
    const SurfaceShader shader = shader_of(r, d.light, d.shadow);
    const std::vector<uint32_t>& ids = profile_.msaa_samples == 1 ? geo.view.visibility().triangle : geo.pixel_ids;
    // Without a sky plugin the background is the ambient radiance: a flat sky.
    const glm::vec3 background = description_.ambient;
    std::vector<uint64_t> shaded_rows(size_t(h), 0);
    jobs.parallel_for("shade", size_t(h), 4, [&](size_t y0, size_t y1) {
      // Pixels of a row are shaded in batches of runs of pixels on one triangle.
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      const Material** materials = q.materials;
      size_t* where = q.where;
      auto flush = [&] {
        q.flush(scene_, emissive, shader,
                [&](size_t pixel, const glm::vec3& c) { buffers.color[pixel] = c; });
      };
      // Neighbouring pixels mostly see the same triangle: set it up once.
      uint32_t current_id = kNoTriangle;
      std::optional<TriangleSurface> triangle;
      const TriangleInterp* interp = nullptr;
      const Material* material = nullptr;
      for (size_t y = y0; y < y1; ++y) {
        uint64_t n = 0;
        for (int x = 0; x < w;) {
          const size_t i = y * size_t(w) + size_t(x);
          if (ids[i] == kNoTriangle || is_edge_pixel(ids[i])) {  // edge pixels: their fragments, below
            buffers.color[i] = background;
            ++x;
            continue;
          }
          if (ids[i] != current_id) {
            triangle.emplace(triangle_of(geo, ids[i], material));
            interp = &geo.view.interp(ids[i]);
            current_id = ids[i];
          }
          // The run of pixels on this triangle, as far as the batch has room.
          const int room = SurfaceBatch::kCapacity - surfaces.count;
          int span = 1;
          while (span < room && x + span < w && ids[i + size_t(span)] == current_id) ++span;
          for (int k = 0; k < span; ++k) {
            where[surfaces.count + k] = i + size_t(k);
            materials[surfaces.count + k] = material;
          }
          triangle->add_span(surfaces, *interp, x, span, int(y));
          if (surfaces.full()) flush();
          x += span;
          n += uint64_t(span);
        }
        shaded_rows[y] = n;
      }
      if (surfaces.count > 0) flush();
    });
    // Edge pixels' fragments, each at its samples' centroid (inside its
    // triangle: no extrapolated attributes), in batches.
    std::vector<EdgeFragment>& fragments = buffers.fragments;
    const std::vector<size_t> chunks = fragment_chunks(fragments, 256);
    jobs.parallel_for("shade fragments", chunks.size() - 1, 1, [&](size_t c0, size_t c1) {
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      float px[SurfaceBatch::kCapacity], py[SurfaceBatch::kCapacity];
      auto flush = [&] {
        q.flush(scene_, emissive, shader,
                [&](size_t f, const glm::vec3& c) { fragments[f].color = c; });
      };
      // A pixel's fragments lie on different triangles, its neighbours' on
      // the same ones: visiting the chunk's fragments by triangle gives runs
      // that share one triangle set-up. (Each point's shading is its own:
      // the order changes no result.)
      std::vector<std::pair<uint32_t, uint32_t>> order;  // (triangle, fragment)
      for (size_t f = chunks[c0]; f < chunks[c1]; ++f) {
        if (fragments[f].triangle == kNoTriangle)
          fragments[f].color = background;
        else
          order.emplace_back(fragments[f].triangle, uint32_t(f));
      }
      std::sort(order.begin(), order.end());
      std::optional<TriangleSurface> triangle;
      const Material* material = nullptr;
      for (size_t o = 0; o < order.size();) {
        const uint32_t id = order[o].first;
        triangle.emplace(triangle_of(geo, id, material));
        const TriangleInterp& interp = geo.view.interp(id);
        while (o < order.size() && order[o].first == id) {
          const int room = SurfaceBatch::kCapacity - surfaces.count;
          int span = 0;
          for (; span < room && o + size_t(span) < order.size() && order[o + size_t(span)].first == id; ++span) {
            const size_t k = order[o + size_t(span)].second;
            q.where[surfaces.count + span] = k;
            q.materials[surfaces.count + span] = material;
            px[span] = fragments[k].x;
            py[span] = fragments[k].y;
          }
          triangle->add_points(surfaces, interp, px, py, span);
          if (surfaces.full()) flush();
          o += size_t(span);
        }
      }
      if (surfaces.count > 0) flush();
    });
    uint64_t total = 0;
    for (uint64_t n : shaded_rows) total += n;  // fixed-order reduction
    pixels_shaded_ = total;
  });

  struct TransparentData {
    FrameGraphId<Geometry> visibility;
    FrameGraphId<ShadowMap> shadow;
    FrameGraphId<LightEnvironment> light;
    FrameGraphId<FrameBuffers> depth, color;
  };
  if (!geo.blended.empty())
    graph.add_pass<TransparentData>("transparent", [&](Builder& b, TransparentData& d) {
      // Blended draws rasterize through the view's rasterizer (its bins).
      b.read(visibility);
      d.visibility = visibility = b.write(visibility);
      d.shadow = b.read(engine.shadow);
      d.light = b.read(engine.light);
      d.depth = b.read(engine.depth);
      b.read(color);
      d.color = color = b.write(color);
    }, [this, &triangle_of, &shader_of, &cam, w](const Resources& r, const TransparentData& d) {
    Geometry& geo = r.get_mutable(d.visibility);
    FrameBuffers& buffers = r.get_mutable(d.color);
    const SurfaceShader shader = shader_of(r, d.light, d.shadow);
    std::vector<EdgeFragment>& fragments = buffers.fragments;
    // Over a share `coverage` of the pixel the surface blends with its alpha:
    // on the pixel's box that is alpha * coverage over all of it.
    auto blend = [](glm::vec3& dst, const glm::vec3& c, float a) { dst = dst * (1.0f - a) + c * a; };
    const FragmentFn fragment = [&](int x, int y, uint32_t id, const Barycentrics& bary, float coverage) {
      const Material* m = nullptr;
      const SurfaceSample surface = triangle_of(geo, id, m).at(bary);
      const glm::vec4 shaded = shader.shade(*m, surface);
      const glm::vec3 c(shaded);
      const float a = shaded.a * coverage;
      const size_t pixel = size_t(y) * size_t(w) + size_t(x);
      blend(buffers.color[pixel], c, a);
      if (fragments.empty() || !is_edge_pixel(geo.pixel_ids[pixel])) return;
      // An edge pixel: the surface, seen at its samples' centroid, covers the
      // fragments behind it (its coverage spread evenly over them).
      const float dist = float(glm::length(glm::dvec3(surface.position) - cam.position));
      for (size_t f = first_fragment(geo.pixel_ids[pixel]); f < fragments.size() && fragments[f].pixel == pixel; ++f)
        if (fragments[f].distance > dist) blend(fragments[f].color, c, a);
    };
    geo.view.render_blended(r.jobs(), geo.blended, fragment,
                            profile_.msaa_samples == 1 ? std::span<const float>() : std::span<const float>(buffers.depth));
  });

  std::vector<Plugin*> compositors;
  for (auto& p : plugins_)
    if (p->has_composite()) compositors.push_back(p.get());
  struct CompositeData {
    FrameGraphId<FrameBuffers> depth, color;
  };
  if (!compositors.empty())
    graph.add_pass<CompositeData>("composite", [&](Builder& b, CompositeData& d) {
      d.depth = b.read(engine.depth);
      b.read(color);
      for (Plugin* p : compositors)
        for (const FrameGraphHandle& h : p->composite_reads()) b.read(h);
      d.color = color = b.write(color);
    }, [&compositors, w, h](const Resources& r, const CompositeData& d) {
      FrameBuffers& buffers = r.get_mutable(d.color);
      JobSystem& jobs = r.jobs();
      for_each_composite_strip(jobs, "composite", w, h, [&](int x0, int y0, int x1, int y1) {
        for (Plugin* p : compositors) p->composite(buffers, x0, y0, x1, y1);
      });
      std::vector<EdgeFragment>& fragments = buffers.fragments;
      const size_t grain = 512, n = (fragments.size() + grain - 1) / grain;
      jobs.parallel_for("composite fragments", n, 1, [&](size_t c0, size_t c1) {
        const size_t f0 = c0 * grain, f1 = std::min(c1 * grain, fragments.size());
        for (Plugin* p : compositors) p->composite_fragments(buffers, std::span<EdgeFragment>(&fragments[f0], f1 - f0));
      });
    });

  struct ResolveData {
    FrameGraphId<FrameBuffers> color, display;
  };
  graph.add_pass<ResolveData>("resolve", [&](Builder& b, ResolveData& d) {
    b.read(color);
    d.color = color = b.write(color);  // edge pixels' fragments resolve into their pixels
    d.display = display = b.write(display);
  }, [this, w, h](const Resources& r, const ResolveData& d) {
    FrameBuffers& buffers = r.get_mutable(d.color);
    JobSystem& jobs = r.jobs();
    if (!display_ || display_->ev100() != description_.exposure_ev100)
      display_ = std::make_unique<DisplayTransform>(description_.exposure_ev100);
    resolve_fragments(buffers.fragments, buffers.color, jobs);
    jobs.parallel_for("resolve", size_t(h), 16, [&](size_t y0, size_t y1) {
      display_->resolve(&buffers.color[y0 * size_t(w)], (y1 - y0) * size_t(w), &buffers.display[y0 * size_t(w) * 3]);
    });
  });
  graph.mark_output(display);

  graph.compile();
  jobs_.take_records();
  record_ = FrameRecord{};
  record_.frame = frame;
  record_.begin_us = jobs_.now_us();
  graph.execute(jobs_);
  record_.frame_ms = (jobs_.now_us() - record_.begin_us) * 1e-3;
  record_.passes = graph.timings();
  if (pose_) {  // playback's posing is part of the frame's cost
    record_.frame_ms += pose.ms();
    record_.passes.insert(record_.passes.begin(), pose);
  }
  record_.culled = graph.culled_pass_names();
  record_.jobs = jobs_.take_records();
  const RasterStats& st = geo.stats;
  uint64_t mixed_pixels = 0;  // pixels whose samples see more than one triangle
  for (const MixedSamples& m : geo.view.visibility().mixed) mixed_pixels += m.pixels.size();
  record_.raster = {{"triangles_in", st.triangles_in},       {"triangles_culled", st.triangles_culled},
                    {"triangles_clipped", st.triangles_clipped}, {"triangles_visible", st.triangles_visible},
                    {"tile_triangle_pairs", st.tile_triangle_pairs}, {"pixels_covered", st.pixels_covered},
                    {"pixels_shaded", pixels_shaded_},
                    {"msaa_mixed_pixels", mixed_pixels}, {"edge_fragments", buffers_.fragments.size()},    {"draws_in_view", geo.opaque.size() + geo.blended.size()},
                    {"shadow_casters", geo.casters.size()}, {"shadow_map_reused", geo.shadow_reused}};
  for (auto& p : plugins_) p->report_frame(record_.plugins[p->name()]);
  return record_;
}

}  // namespace cr
