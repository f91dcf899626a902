#include "atmosphere/lut_scheduler.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "atmosphere/model_spectrum.h"
#include "engine/core/math_constants.h"

namespace cr {

namespace {

double angle_deg_f(const glm::vec3& a, const glm::vec3& b) {
  const double c = std::clamp(double(glm::dot(a, b)), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPiD;
}

double sun_zenith_deg(const FroxelCamera& c) {
  const glm::dvec3 up = c.position / glm::length(c.position);
  const double mu = std::clamp(glm::dot(glm::dvec3(c.sun_direction), up), -1.0, 1.0);
  return std::acos(mu) * 180.0 / kPiD;
}

// The altitude a sky-view LUT is built for: the ground below it, and inside
// the atmosphere its top above it (the sky is the same from anywhere higher
// up to the space fallback, which builds it for the true altitude).
double skyview_altitude(double altitude, double top, double space_altitude) {
  return altitude > space_altitude ? altitude : std::clamp(altitude, 0.0, top);
}

}  // namespace

double AtmosphereFrameInputs::radius() const { return glm::length(camera.position); }
double AtmosphereFrameInputs::altitude() const { return radius() - ground_radius; }

size_t slice_begin(size_t items, size_t granule, int s, int slices) {
  const size_t units = (items + granule - 1) / granule;
  return std::min(items, units * size_t(s) / size_t(slices) * granule);
}

LutScheduler::LutScheduler(const AtmosphereSettings& settings)
    : LutScheduler(settings, lut_sampling(settings.spectral_samples)) {}

LutScheduler::LutScheduler(const AtmosphereSettings& settings, SpectralSampling sampling)
    : settings_(settings), sampling_(std::move(sampling)) {
  group_models_ = group_models(model_);
}

std::vector<AtmosphereModel> LutScheduler::group_models(const AtmosphereModel& model) const {
  if (sampling_.rgb) return {model};
  std::vector<AtmosphereModel> groups;
  for (int g = 0; g < sampling_.groups(); ++g) {
    const double* w = &sampling_.wavelengths_nm[size_t(3 * g)];
    groups.push_back(model_at_wavelengths(model, {w[0], w[1], w[2]}));
  }
  return groups;
}

void LutScheduler::set_model(const AtmosphereModel& model) {
  if (model == model_) return;
  model_ = model;
  group_models_ = group_models(model_);
  ++model_version_;
}

uint64_t LutScheduler::version(LutKind kind) const {
  switch (kind) {
    case LutKind::Transmittance: return t_.version;
    case LutKind::MultiScattering: return ms_.version;
    case LutKind::SkyView: return sv_.version;
    case LutKind::AerialPerspective: return ap_.version;
  }
  return 0;
}

std::string LutScheduler::invalidation(LutKind kind, const AtmosphereFrameInputs& in, bool against_back,
                                       uint64_t upstream_now) const {
  const double top = model_.atmosphere_height();
  switch (kind) {
    case LutKind::Transmittance:
      return (against_back ? t_.b_upstream : t_.f_upstream) != model_version_ ? "params" : "";
    case LutKind::MultiScattering:
      return (against_back ? ms_.b_upstream : ms_.f_upstream) != upstream_now ? "upstream" : "";
    case LutKind::SkyView: {
      if ((against_back ? sv_.b_upstream : sv_.f_upstream) != upstream_now) return "upstream";
      const FroxelCamera& c = against_back ? sv_.b_camera : sv_.f_camera;
      const double alt_then = skyview_altitude(glm::length(c.position) - model_.bottom_radius, top, settings_.space_altitude);
      const double alt_now = skyview_altitude(in.altitude(), top, settings_.space_altitude);
      if (std::abs(alt_now - alt_then) > settings_.invalidate_camera_m) return "camera";
      if (std::abs(sun_zenith_deg(c) - sun_zenith_deg(in.camera)) > settings_.invalidate_sun_deg) return "sun";
      return "";
    }
    case LutKind::AerialPerspective: {
      if ((against_back ? ap_.b_upstream : ap_.f_upstream) != upstream_now) return "upstream";
      const FroxelCamera& c = against_back ? ap_.b_camera : ap_.f_camera;
      if (glm::length(c.position - in.camera.position) > settings_.invalidate_camera_m) return "camera";
      if (angle_deg_f(c.forward, in.camera.forward) > settings_.invalidate_camera_deg ||
          angle_deg_f(c.up, in.camera.up) > settings_.invalidate_camera_deg)
        return "camera";
      if (c.tan_half_fov != in.camera.tan_half_fov || c.aspect != in.camera.aspect) return "camera";
      if (angle_deg_f(c.sun_direction, in.camera.sun_direction) > settings_.invalidate_sun_deg) return "sun";
      return "";
    }
  }
  return "";
}

bool LutScheduler::drifted(LutKind kind, const AtmosphereFrameInputs& in) const {
  const FroxelCamera& now = in.camera;
  switch (kind) {
    case LutKind::Transmittance:
    case LutKind::MultiScattering:
      return false;  // depend only on the parameters, which invalidate exactly
    case LutKind::SkyView: {
      const FroxelCamera& c = sv_.f_camera;
      const double top = model_.atmosphere_height();
      return skyview_altitude(glm::length(c.position) - model_.bottom_radius, top, settings_.space_altitude) !=
                 skyview_altitude(in.altitude(), top, settings_.space_altitude) ||
             sun_zenith_deg(c) != sun_zenith_deg(now);
    }
    case LutKind::AerialPerspective: {
      const FroxelCamera& c = ap_.f_camera;
      return c.position != now.position || c.forward != now.forward || c.up != now.up ||
             c.sun_direction != now.sun_direction;
    }
  }
  return false;
}

LutWork LutScheduler::decide(LutKind kind, const AtmosphereFrameInputs& in, bool space,
                             const AtmospherePlan& so_far) const {
  LutWork w;
  const size_t k = size_t(kind);
  const LutSchedule& sched = settings_.schedule[k];
  if (space && kind == LutKind::AerialPerspective) return w;

  bool has_front = false, in_progress = false;
  int next_slice = 0, slices = 1, last_start = 0;
  std::string current_cause;
  uint64_t upstream_now = model_version_;
  bool upstream_ready = true;
  auto fill = [&](const auto& slot) {
    has_front = slot.front != nullptr;
    in_progress = !slot.back.empty();
    next_slice = slot.next_slice;
    slices = slot.slices;
    last_start = slot.last_start;
    current_cause = slot.b_cause;
  };
  switch (kind) {
    case LutKind::Transmittance: fill(t_); break;
    case LutKind::MultiScattering:
      fill(ms_);
      upstream_now = t_.version + (so_far.work[0].publishes ? 1 : 0);
      upstream_ready = upstream_now > 0;
      break;
    case LutKind::SkyView:
    case LutKind::AerialPerspective:
      if (kind == LutKind::SkyView) fill(sv_); else fill(ap_);
      upstream_now = ms_.version + (so_far.work[1].publishes ? 1 : 0);
      upstream_ready = upstream_now > 0;
      break;
  }
  if (!upstream_ready) return w;

  auto start = [&](const std::string& cause, bool whole) {
    w.active = true;
    w.restart = true;
    w.slices = whole ? 1 : sched.slices;
    w.slice = 0;
    w.slice_end = 1;
    w.publishes = w.slice_end == w.slices;
    w.cause = cause;
    return w;
  };
  if (settings_.full_schedule) return start("full", true);
  if (!has_front && !in_progress) return start("initial", true);
  if (in_progress) {
    const std::string cause = invalidation(kind, in, true, upstream_now);
    if (!cause.empty()) return start(cause, false);
    w.active = true;
    w.slices = slices;
    w.slice = next_slice;
    w.slice_end = next_slice + 1;
    w.publishes = w.slice_end == slices;
    w.cause = current_cause;
    return w;
  }
  const std::string cause = invalidation(kind, in, false, upstream_now);
  if (!cause.empty()) return start(cause, false);
  if (so_far.frame - last_start >= sched.period && drifted(kind, in)) return start("periodic", false);
  return w;
}

AtmospherePlan LutScheduler::plan(const AtmosphereFrameInputs& inputs) const {
  AtmospherePlan p;
  p.frame = inputs.frame;
  p.inputs = inputs;
  p.space = inputs.altitude() > settings_.space_altitude;
  for (int k = 0; k < kLutKinds; ++k) p.work[size_t(k)] = decide(LutKind(k), inputs, p.space, p);
  return p;
}

ExplicitOrderChoice explicit_orders_for(const AtmosphereModel& model, const AtmosphereSettings& s) {
  return explicit_orders_for(model, s.multiscattering_height, s.multiscattering_directions, s.multiscattering_steps,
                             s.multiscattering_max_fms, s.multiscattering_explicit_orders,
                             s.multiscattering_max_explicit_orders, s.multiscattering_tail_share);
}

std::shared_ptr<MultiScatteringLut> new_multiscattering_lut(const AtmosphereModel& model, const AtmosphereSettings& s,
                                                            int explicit_orders) {
  return std::make_shared<MultiScatteringLut>(model, s.multiscattering_width, s.multiscattering_height,
                                              s.multiscattering_directions, s.multiscattering_steps,
                                              s.multiscattering_max_fms, explicit_orders);
}

void bake_in_jobs(MultiScatteringLut& lut, size_t begin, size_t end, size_t granule, const TransmittanceLut& t,
                  JobSystem& jobs, const std::string& name) {
  for (int p = 0; p < lut.passes(); ++p) {
    const size_t b = std::max(begin, size_t(p) * lut.texel_count());
    const size_t e = std::min(end, size_t(p + 1) * lut.texel_count());
    if (e > b) jobs.parallel_for(name, e - b, granule, [&](size_t x, size_t y) { lut.bake(b + x, b + y, t); });
  }
}

void LutScheduler::run_slices(LutKind kind, size_t items, size_t granule, int slice, int slice_end, int slices,
                              JobSystem& jobs, const std::function<void(size_t, size_t)>& bake) {
  const size_t begin = slice_begin(items, granule, slice, slices);
  const size_t end = slice_begin(items, granule, slice_end, slices);
  if (end > begin)
    jobs.parallel_for(std::string("atmosphere.") + lut_name(kind), end - begin, granule,
                      [&](size_t b, size_t e) { bake(begin + b, begin + e); });
}

namespace {

template <class Lut>
std::vector<const Lut*> raw(const std::vector<std::shared_ptr<Lut>>& luts) {
  std::vector<const Lut*> out;
  for (const auto& l : luts) out.push_back(l.get());
  return out;
}

template <class Lut>
std::vector<std::shared_ptr<const Lut>> to_const(const std::vector<std::shared_ptr<Lut>>& luts) {
  return {luts.begin(), luts.end()};
}

}  // namespace

void LutScheduler::run(LutKind kind, const AtmospherePlan& plan, JobSystem& jobs) {
  const LutWork& w = plan.work[size_t(kind)];
  Timing& timing = timing_[size_t(kind)];
  timing.frame_ms = 0.0;
  if (!w.active) return;
  const auto t0 = std::chrono::steady_clock::now();
  const AtmosphereSettings& s = settings_;
  const size_t groups = group_models_.size();
  auto begin_rebuild = [&](auto& slot) {
    slot.next_slice = 0;
    slot.slices = w.slices;
    slot.last_start = plan.frame;
    slot.b_cause = w.cause;
    slot.b_camera = plan.inputs.camera;
    slot.back.clear();
    timing.building_ms = 0.0;
  };
  // `mixed()` makes a LUT of the groups' shape (and the rebuild's inputs) for them to be mixed into.
  auto finish = [&](auto& slot, auto mixed) {
    const bool complete = w.slice_end >= slot.slices;
    decltype(mixed()) published;
    if (complete) {
      // A complete LUT is mixed and quantised before it is published (inside the pass's time).
      if (slot.back.size() == 1) {
        published = slot.back[0];
      } else {
        published = mixed();
        published->mix_from(raw(slot.back), sampling_, jobs);
      }
      if (s.lut_precision == LutPrecision::Q15) published->quantize_q15();
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    timing.frame_ms = ms;
    timing.building_ms += ms;
    slot.next_slice = w.slice_end;
    if (complete) {
      slot.front = published;
      slot.front_groups = to_const(slot.back);
      slot.back.clear();
      ++slot.version;
      slot.f_upstream = slot.b_upstream;
      slot.f_camera = slot.b_camera;
      slot.built_from = slot.b_t_mixed;
      slot.built_from_groups = slot.b_t;
      timing.full_ms = timing.building_ms;
    }
  };
  switch (kind) {
    case LutKind::Transmittance: {
      auto make = [&](const AtmosphereModel& m) {
        return std::make_shared<TransmittanceLut>(m, s.transmittance_width, s.transmittance_height, s.transmittance_steps);
      };
      if (w.restart) {
        begin_rebuild(t_);
        for (const AtmosphereModel& m : group_models_) t_.back.push_back(make(m));
        t_.b_upstream = model_version_;
      }
      for (const auto& lut : t_.back)
        run_slices(kind, lut->texel_count(), size_t(s.transmittance_width), w.slice, w.slice_end, t_.slices, jobs,
                   [&](size_t b, size_t e) { lut->bake(b, e); });
      finish(t_, [&] { return make(model_); });
      break;
    }
    case LutKind::MultiScattering: {
      if (w.restart) {
        begin_rebuild(ms_);
        ms_.b_t_mixed = t_.front;
        ms_.b_t = t_.front_groups;
        ms_.b_upstream = t_.version;
        ms_orders_.resize(groups);
        ms_orders_model_.resize(groups);
        for (size_t g = 0; g < groups; ++g) {
          const AtmosphereModel& m = ms_.b_t[g]->model();
          if (!ms_orders_model_[g] || !(*ms_orders_model_[g] == m)) {
            ms_orders_[g] = explicit_orders_for(m, s);
            ms_orders_model_[g] = m;
          }
          ms_.back.push_back(new_multiscattering_lut(m, s, ms_orders_[g].orders));
        }
      }
      const size_t granule = size_t(s.multiscattering_width);
      for (size_t g = 0; g < groups; ++g) {
        MultiScatteringLut& lut = *ms_.back[g];
        bake_in_jobs(lut, slice_begin(lut.work_items(), granule, w.slice, ms_.slices),
                     slice_begin(lut.work_items(), granule, w.slice_end, ms_.slices), granule, *ms_.b_t[g], jobs,
                     std::string("atmosphere.") + lut_name(kind));
      }
      finish(ms_, [&] { return new_multiscattering_lut(ms_.b_t_mixed->model(), s, ms_orders_[0].orders); });
      break;
    }
    case LutKind::SkyView: {
      const glm::dvec3 up = plan.inputs.camera.position / plan.inputs.radius();
      const float mu_s = float(std::clamp(glm::dot(glm::dvec3(plan.inputs.camera.sun_direction), up), -1.0, 1.0));
      const AtmosphereModel& m = ms_.built_from->model();
      const float altitude = float(skyview_altitude(plan.inputs.altitude(), m.atmosphere_height(), s.space_altitude));
      // Limb rays seen from space cross the whole shell: they get the space march's step count.
      const int max_steps = plan.space ? std::max(s.skyview_max_steps, s.space_steps) : s.skyview_max_steps;
      auto make = [&] {
        return std::make_shared<SkyViewLut>(s.skyview_width, s.skyview_height, s.skyview_min_steps, max_steps,
                                            altitude, mu_s, m.bottom_radius, m.top_radius);
      };
      if (w.restart) {
        begin_rebuild(sv_);
        sv_.b_t_mixed = ms_.built_from;
        sv_.b_t = ms_.built_from_groups;
        sv_.b_ms = ms_.front_groups;
        sv_.b_upstream = ms_.version;
        for (size_t g = 0; g < groups; ++g) sv_.back.push_back(make());
      }
      for (size_t g = 0; g < groups; ++g) {
        SkyViewLut& lut = *sv_.back[g];
        const AtmosphereLuts luts{sv_.b_t[g]->model(), *sv_.b_t[g], *sv_.b_ms[g]};
        run_slices(kind, lut.texel_count(), size_t(s.skyview_width), w.slice, w.slice_end, sv_.slices, jobs,
                   [&](size_t b, size_t e) { lut.bake(b, e, luts); });
      }
      // Mixed into a copy of a group's LUT: the inputs its rebuild started with, not this frame's.
      finish(sv_, [&] { return std::make_shared<SkyViewLut>(*sv_.back[0]); });
      break;
    }
    case LutKind::AerialPerspective: {
      auto make = [&] {
        return std::make_shared<AerialPerspectiveLut>(s.ap_width, s.ap_height, s.ap_depth, s.ap_km_per_slice,
                                                      s.ap_steps_per_slice, plan.inputs.camera);
      };
      if (w.restart) {
        begin_rebuild(ap_);
        ap_.b_t_mixed = ms_.built_from;
        ap_.b_t = ms_.built_from_groups;
        ap_.b_ms = ms_.front_groups;
        ap_.b_upstream = ms_.version;
        for (size_t g = 0; g < groups; ++g) ap_.back.push_back(make());
      }
      for (size_t g = 0; g < groups; ++g) {
        AerialPerspectiveLut& lut = *ap_.back[g];
        const AtmosphereLuts luts{ap_.b_t[g]->model(), *ap_.b_t[g], *ap_.b_ms[g]};
        run_slices(kind, lut.column_count(), size_t(s.ap_width), w.slice, w.slice_end, ap_.slices, jobs,
                   [&](size_t b, size_t e) { lut.bake(b, e, luts); });
      }
      finish(ap_, [&] { return std::make_shared<AerialPerspectiveLut>(*ap_.back[0]); });
      break;
    }
  }
}

void LutScheduler::run_all(const AtmospherePlan& plan, JobSystem& jobs) {
  for (int k = 0; k < kLutKinds; ++k) run(LutKind(k), plan, jobs);
}

nlohmann::json LutScheduler::report(const AtmospherePlan& plan) const {
  nlohmann::json j = nlohmann::json::object();
  double amortised_total = 0.0, frame_total = 0.0;
  for (int k = 0; k < kLutKinds; ++k) {
    const LutWork& w = plan.work[size_t(k)];
    const Timing& t = timing_[size_t(k)];
    const LutSchedule& sched = settings_.schedule[size_t(k)];
    const double period = settings_.full_schedule ? 1.0 : double(sched.period);
    const double frame_ms = w.active ? t.frame_ms : 0.0;
    nlohmann::json e = {{"updated", w.active},
                        {"cause", w.cause},
                        {"frame_ms", frame_ms},
                        {"full_ms", t.full_ms},
                        {"amortised_ms", t.full_ms / period},
                        {"period", int(period)},
                        {"slices", settings_.full_schedule ? 1 : sched.slices},
                        {"version", version(LutKind(k))}};
    if (w.active) {
      e["slice"] = w.slice;
      e["slice_count"] = w.slices;
      e["published"] = w.publishes;
      e["per_slice_ms"] = frame_ms / double(std::max(1, w.slice_end - w.slice));
    }
    amortised_total += t.full_ms / period;
    frame_total += frame_ms;
    j[lut_name(LutKind(k))] = e;
  }
  j["frame_ms"] = frame_total;
  j["amortised_ms"] = amortised_total;
  j["space_fallback"] = plan.space;
  if (ms_.front) {
    j["multiscattering_clamped_texels"] = ms_.front->clamped_texels();
    j["multiscattering_max_fms"] = ms_.front->max_fms_seen();
    j["multiscattering_explicit_orders"] = ms_.front->explicit_orders();
  }
  return j;
}

}  // namespace cr
