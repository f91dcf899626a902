#include "atmosphere/sky_environment.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "atmosphere/sky_composite.h"
#include "engine/core/math_constants.h"

namespace cr {

namespace {

double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180.0 / kPiD;
}

}  // namespace

EnvironmentPrefilter::Radiance sky_environment_radiance(const SkyFrame& f) {
  return [&f](size_t n, const float* dx, const float* dy, const float* dz, glm::vec3* out) {
    sky_radiance_batch(f, n, dx, dy, dz, out);
  };
}

std::shared_ptr<const SpecularEnvironment> bake_sky_environment(const SkyFrame& f, const AtmosphereSettings& s,
                                                                JobSystem& jobs) {
  return prefilter_environment(s.environment_size, s.environment_levels, s.environment_samples,
                               sky_environment_radiance(f), jobs);
}

SkyEnvironment::SkyEnvironment(const AtmosphereSettings& settings) : settings_(settings) {}

SkyEnvironment::Inputs SkyEnvironment::inputs_of(const AtmospherePlan& plan, uint64_t upstream) {
  Inputs in;
  in.frame = plan.frame;
  in.sun = plan.inputs.camera.sun_direction;
  const double r = plan.inputs.radius();
  in.up = r > 0.0 ? plan.inputs.camera.position / r : glm::dvec3(0.0, 1.0, 0.0);
  in.altitude = plan.inputs.altitude();
  in.upstream = upstream;
  return in;
}

std::string SkyEnvironment::invalidation(const Inputs& now) const {
  const Inputs& was = front_inputs_;
  if (was.upstream != now.upstream) return "upstream";
  if (angle_deg(glm::dvec3(was.sun), glm::dvec3(now.sun)) > settings_.invalidate_sun_deg) return "sun";
  if (std::abs(was.altitude - now.altitude) > settings_.invalidate_camera_m ||
      angle_deg(was.up, now.up) > settings_.invalidate_camera_deg)
    return "camera";
  return "";
}

EnvironmentWork SkyEnvironment::plan(const AtmospherePlan& plan, uint64_t upstream) const {
  EnvironmentWork w;
  if (upstream == 0) return w;  // no sky yet
  auto start = [&](const std::string& cause, int slices) {
    w.active = true;
    w.restart = true;
    w.slice = 0;
    w.slices = slices;
    w.publishes = slices == 1;
    w.cause = cause;
    return w;
  };
  const LutSchedule& sched = settings_.environment_schedule;
  if (settings_.full_schedule) return start("full", 1);
  if (back_) {
    w.active = true;
    w.slice = next_slice_;
    w.slices = slices_;
    w.publishes = next_slice_ + 1 == slices_;
    w.cause = back_cause_;
    return w;
  }
  if (!front_) return start("initial", 1);
  const Inputs now = inputs_of(plan, upstream);
  const std::string cause = invalidation(now);
  if (!cause.empty()) return start(cause, sched.slices);
  const Inputs& was = front_inputs_;
  const bool drifted = was.sun != now.sun || was.altitude != now.altitude || was.up != now.up;
  // The period counts from the last rebuild's start, as the LUTs' does.
  if (plan.frame - was.frame >= sched.period && drifted) return start("periodic", sched.slices);
  return w;
}

void SkyEnvironment::run(const EnvironmentWork& w, const AtmospherePlan& plan, uint64_t upstream, const SkyFrame& sky,
                         JobSystem& jobs) {
  frame_ms_ = 0.0;
  if (!w.active || !sky.valid) return;
  const auto t0 = std::chrono::steady_clock::now();
  if (w.restart) {
    back_ = std::make_unique<EnvironmentPrefilter>(settings_.environment_size, settings_.environment_levels,
                                                   settings_.environment_samples);
    back_sky_ = std::make_unique<SkyFrame>(sky);
    back_inputs_ = inputs_of(plan, upstream);
    next_slice_ = 0;
    slices_ = w.slices;
    back_cause_ = w.cause;
    building_ms_ = 0.0;
  }
  back_->run(back_->slice_begin(w.slice, slices_), back_->slice_begin(w.slice + 1, slices_), sky_environment_radiance(*back_sky_), jobs, "atmosphere.environment");
  next_slice_ = w.slice + 1;
  // Quantised before it is published, inside the pass's time.
  if (back_->complete() && settings_.lut_precision == LutPrecision::Q15) back_->quantize_result_q15();
  frame_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  building_ms_ += frame_ms_;
  if (back_->complete()) {
    front_ = back_->result();
    front_inputs_ = back_inputs_;
    ++version_;
    full_ms_ = building_ms_;
    back_.reset();
    back_sky_.reset();
  }
}

nlohmann::json SkyEnvironment::report(const EnvironmentWork& w, int frame) const {
  const double period = settings_.full_schedule ? 1.0 : double(settings_.environment_schedule.period);
  nlohmann::json e = {{"updated", w.active},
                      {"cause", w.cause},
                      {"frame_ms", w.active ? frame_ms_ : 0.0},
                      {"full_ms", full_ms_},
                      {"amortised_ms", full_ms_ / period},
                      {"period", int(period)},
                      {"slices", settings_.full_schedule ? 1 : settings_.environment_schedule.slices},
                      {"version", version_},
                      {"age_frames", front_ ? frame - front_inputs_.frame : -1},
                      {"size", settings_.environment_size},
                      {"levels", settings_.environment_levels},
                      {"samples", settings_.environment_samples}};
  if (w.active) {
    e["slice"] = w.slice;
    e["slice_count"] = w.slices;
    e["published"] = w.publishes;
  }
  return e;
}

}  // namespace cr
