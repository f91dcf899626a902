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
  uint64_t pixels_shaded = 0;
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
  FrameContext ctx{scene_, description_, profile_, jobs_, view, buffers_, light_, shadow_, previous_shadow_};
  const int w = buffers_.width, h = buffers_.height;
  const int tile = profile_.tile_size;
  const bool sun_up = view.sun_direction.y > 0.0f && glm::length(view.sun_illuminance) > 0.0f;

  FrameGraph graph;

  graph.add_pass("light", [](FrameGraph::Builder& b) { b.write("light_environment"); }, [this, &view, sun_up] {
    light_ = LightEnvironment{};
    light_.sun_direction = view.sun_direction;
    light_.sun_illuminance = sun_up ? view.sun_illuminance : glm::vec3(0.0f);
    light_.ambient_sh = sh_constant_radiance(description_.ambient);
  });

  const bool shadows = profile_.shadow_map_size > 0 && sun_up;
  if (shadows)
    graph.add_pass("shadow", [](FrameGraph::Builder& b) { b.write("shadow_map"); }, [this, &geo, &view] {
      ShadowMap fit = fit_shadow_projection(view.camera, view.sun_direction, profile_.shadow_distance,
                                     profile_.shadow_map_size, profile_.shadow_pcf_radius, scene_.bounds_min,
                                     scene_.bounds_max);
      // A still scene: when the texel-snapped projection has not moved, last
      // frame's map is exactly what a new render would produce.
      const bool unchanged = !pose_ && fit.size == shadow_.size && fit.light_view_proj == shadow_.light_view_proj &&
                             fit.origin == shadow_.origin && fit.direction_to_sun == shadow_.direction_to_sun;
      if (unchanged) {
        previous_shadow_.size = 0;  // nothing to compare against (its memory is kept for the next render)
        geo.shadow_reused = true;
        return;
      }
      // Last frame's map becomes the previous one (temporal plugins compare
      // against it when the sun moves); the new map renders into the memory
      // of the one before (the render writes every texel).
      fit.depth.swap(previous_shadow_.depth);
      previous_shadow_ = std::move(shadow_);
      shadow_ = std::move(fit);
      geo.shadow_reused = false;
      geo.casters.clear();
      for (uint32_t i = 0; i < scene_.draws.size(); ++i) {
        const Draw& d = scene_.draws[i];
        const Material& m = material_of(scene_, scene_.primitive(d));
        if (m.alpha_mode == AlphaMode::Blend) continue;  // translucent surfaces cast no shadow
        if (!aabb_in_ortho(shadow_.light_view_proj, shadow_.origin, d.world_bounds_min, d.world_bounds_max)) continue;
        geo.casters.push_back({&scene_.primitive(d), model_to_clip(shadow_.light_view_proj, shadow_.origin, d.world),
                               true, d.mirrored, m.alpha_mode == AlphaMode::Mask, i});
      }
      geo.shadow.render_depth(jobs_, shadow_.size, profile_.tile_size, geo.casters, shadow_.depth,
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

  graph.add_pass("geometry", [](FrameGraph::Builder& b) { b.write("visibility").write("depth"); },
                 [this, &geo, &cam, w, h, tile] {
    geo.stats = geo.view.render_visibility(jobs_, w, h, tile, geo.opaque, alpha_coverage(scene_, geo.view),
                                           profile_.msaa_samples);
    if (profile_.msaa_samples == 1) {
      buffers_.depth = geo.view.visibility().depth;
      buffers_.fragments.clear();
    } else {
      classify_samples(geo.view, cam, jobs_, geo.pixel_ids, buffers_.depth, buffers_.fragments,
                       geo.fragment_rows);
    }
    view_distances(cam, w, h, buffers_.depth, buffers_.distance, jobs_);
  });

  // Plugins declare their passes after the engine's inputs exist, so their
  // reads of "shadow_map", "depth" and "light_environment" resolve to them.
  for (auto& p : plugins_) p->add_passes(graph, ctx);

  // An orthographic view's rays are parallel: shading takes its view vectors
  // from a point 10^7 m back along them, whose directions differ from -forward
  // by less than the scene's extent / 10^7 radians.
  const glm::dvec3 eye = cam.orthographic ? cam.position - glm::dvec3(cam.forward) * 1e7 : cam.position;
  const ShadingInputs shading{&scene_, &light_, &shadow_, eye, emissive_luminance(description_)};
  // Built by the passes that shade: the light and shadow passes have run then.
  std::optional<SurfaceShader> shader;
  // TEXCOORD_1 is interpolated for materials reading it; most scenes have none.
  const bool any_uv1 =
      std::any_of(scene_.materials.begin(), scene_.materials.end(), [](const Material& m) { return needs_uv1(m); });
  // The triangle a visibility-buffer id names, in world space, and its material.
  auto triangle_of = [this, &geo, any_uv1](uint32_t id, const Material*& material) {
    const TriangleRef r = geo.view.ref(id);
    const Draw& d = scene_.draws[r.draw_index];
    const Primitive& prim = scene_.primitive(d);
    material = &material_of(scene_, prim);
    return TriangleSurface(prim, d, r.triangle_index, r.front_facing, needs_tangent(*material),
                           any_uv1 && needs_uv1(*material));
  };

  graph.add_pass("shade", [](FrameGraph::Builder& b) {
    b.read("visibility").read("shadow_map").read("light_environment").write("hdr_color");
  }, [this, &geo, &triangle_of, &shader, &shading, w, h] {
    shader.emplace(shading);
    const std::vector<uint32_t>& ids = profile_.msaa_samples == 1 ? geo.view.visibility().triangle : geo.pixel_ids;
    // Without a sky plugin the background is the ambient radiance: a flat sky.
    const glm::vec3 background = description_.ambient;
    std::vector<uint64_t> shaded_rows(size_t(h), 0);
    jobs_.parallel_for("shade", size_t(h), 4, [&](size_t y0, size_t y1) {
      // Pixels of a row are shaded in batches of runs of pixels on one triangle.
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      const Material** materials = q.materials;
      size_t* where = q.where;
      auto flush = [&] {
        q.flush(scene_, shading.emissive_luminance, *shader,
                [&](size_t pixel, const glm::vec3& c) { buffers_.color[pixel] = c; });
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
            buffers_.color[i] = background;
            ++x;
            continue;
          }
          if (ids[i] != current_id) {
            triangle.emplace(triangle_of(ids[i], material));
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
    std::vector<EdgeFragment>& fragments = buffers_.fragments;
    const std::vector<size_t> chunks = fragment_chunks(fragments, 256);
    jobs_.parallel_for("shade fragments", chunks.size() - 1, 1, [&](size_t c0, size_t c1) {
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      float px[SurfaceBatch::kCapacity], py[SurfaceBatch::kCapacity];
      auto flush = [&] {
        q.flush(scene_, shading.emissive_luminance, *shader,
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
        triangle.emplace(triangle_of(id, material));
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
    geo.pixels_shaded = total;
  });

  if (!geo.blended.empty())
    graph.add_pass("transparent", [](FrameGraph::Builder& b) { b.read("hdr_color").write("hdr_color"); },
                 [this, &geo, &triangle_of, &shader, &shading, &cam, w] {
    shader.emplace(shading);
    std::vector<EdgeFragment>& fragments = buffers_.fragments;
    // Over a share `coverage` of the pixel the surface blends with its alpha:
    // on the pixel's box that is alpha * coverage over all of it.
    auto blend = [](glm::vec3& dst, const glm::vec3& c, float a) { dst = dst * (1.0f - a) + c * a; };
    const FragmentFn fragment = [&](int x, int y, uint32_t id, const Barycentrics& bary, float coverage) {
      const Material* m = nullptr;
      const SurfaceSample surface = triangle_of(id, m).at(bary);
      const glm::vec4 shaded = shader->shade(*m, surface);
      const glm::vec3 c(shaded);
      const float a = shaded.a * coverage;
      const size_t pixel = size_t(y) * size_t(w) + size_t(x);
      blend(buffers_.color[pixel], c, a);
      if (fragments.empty() || !is_edge_pixel(geo.pixel_ids[pixel])) return;
      // An edge pixel: the surface, seen at its samples' centroid, covers the
      // fragments behind it (its coverage spread evenly over them).
      const float d = float(glm::length(glm::dvec3(surface.position) - cam.position));
      for (size_t f = first_fragment(geo.pixel_ids[pixel]); f < fragments.size() && fragments[f].pixel == pixel; ++f)
        if (fragments[f].distance > d) blend(fragments[f].color, c, a);
    };
    geo.view.render_blended(jobs_, geo.blended, fragment,
                            profile_.msaa_samples == 1 ? std::span<const float>() : std::span<const float>(buffers_.depth));
  });

  std::vector<Plugin*> compositors;
  std::vector<std::string> composite_reads = {"hdr_color"};
  for (auto& p : plugins_)
    if (p->has_composite()) {
      compositors.push_back(p.get());
      for (const std::string& r : p->composite_reads()) composite_reads.push_back(r);
    }
  if (!compositors.empty())
    graph.add_pass("composite", [&](FrameGraph::Builder& b) {
      for (const std::string& r : composite_reads) b.read(r);
      b.write("hdr_color");
    }, [this, &ctx, &compositors, w, h] {
      for_each_composite_strip(jobs_, "composite", w, h, [&](int x0, int y0, int x1, int y1) {
        for (Plugin* p : compositors) p->composite(ctx, x0, y0, x1, y1);
      });
      std::vector<EdgeFragment>& fragments = buffers_.fragments;
      const size_t grain = 512, n = (fragments.size() + grain - 1) / grain;
      jobs_.parallel_for("composite fragments", n, 1, [&](size_t c0, size_t c1) {
        const size_t f0 = c0 * grain, f1 = std::min(c1 * grain, fragments.size());
        for (Plugin* p : compositors) p->composite_fragments(ctx, std::span<EdgeFragment>(&fragments[f0], f1 - f0));
      });
    });

  graph.add_pass("resolve", [](FrameGraph::Builder& b) { b.read("hdr_color").write("frame"); }, [this, w, h] {
    if (!display_ || display_->ev100() != description_.exposure_ev100)
      display_ = std::make_unique<DisplayTransform>(description_.exposure_ev100);
    resolve_fragments(buffers_.fragments, buffers_.color, jobs_);
    jobs_.parallel_for("resolve", size_t(h), 16, [&](size_t y0, size_t y1) {
      display_->resolve(&buffers_.color[y0 * size_t(w)], (y1 - y0) * size_t(w), &buffers_.display[y0 * size_t(w) * 3]);
    });
  });
  graph.mark_output("frame");

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
                    {"pixels_shaded", geo.pixels_shaded},
                    {"msaa_mixed_pixels", mixed_pixels}, {"edge_fragments", buffers_.fragments.size()},    {"draws_in_view", geo.opaque.size() + geo.blended.size()},
                    {"shadow_casters", geo.casters.size()}, {"shadow_map_reused", geo.shadow_reused}};
  for (auto& p : plugins_) p->report_frame(record_.plugins[p->name()]);
  return record_;
}

}  // namespace cr
