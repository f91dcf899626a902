#include "atmosphere/tools/sky_case.h"

#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "atmosphere/planet_frame.h"
#include "engine/core/colorimetry.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/core/math_constants.h"

namespace cr {

namespace {

const char* const kCommandLine = "command line";

}  // namespace

void add_sky_setup_options(ArgParser& p) {
  p.option("preset", "NAME", "atmosphere preset (earth-clear, earth-hazy, earth-thin, earth-dense, mars-like, reference)",
           "earth-clear")
      .option("scene", "FILE", "a scene file whose \"atmosphere\" section is measured (instead of --preset)")
      .option("profile", "FILE", "a profile file whose \"atmosphere\" section sets the LUTs (default: built-in)")
      .option("threads", "N", "worker threads (default: all cores)");
}

SkySetup load_sky_setup(const ArgParser& p) {
  SkySetup s;
  if (p.has("scene")) {
    const std::string path = p.get("scene");
    const nlohmann::json doc = load_json_file(path);
    if (!doc.is_object() || !doc.contains("atmosphere"))
      throw InputError(path, "atmosphere: the scene has no atmosphere section");
    s.scene = parse_atmosphere_scene(doc["atmosphere"], path);
  } else {
    s.scene = parse_atmosphere_scene(nlohmann::json{{"preset", p.get("preset")}}, kCommandLine);
  }
  if (p.has("profile")) {
    const std::string path = p.get("profile");
    const nlohmann::json doc = load_json_file(path);
    s.settings = parse_atmosphere_settings(doc.is_object() && doc.contains("atmosphere") ? doc["atmosphere"]
                                                                                         : nlohmann::json(),
                                           path);
  }
  return s;
}

SkyCase make_sky_case(const SkySetup& setup, const AtmosphereSettings& settings) {
  SkyCase c;
  c.luts = std::make_unique<LutScheduler>(settings);
  c.luts->set_model(setup.scene.model);
  c.offset = planet_offset(setup.scene);
  return c;
}

void update_sky_case(SkyCase& c, int frame, const Camera& camera, const glm::vec3& sun, const glm::vec3& illuminance,
                     JobSystem& jobs) {
  c.camera = camera;
  c.plan = c.luts->plan(frame_inputs(c.luts->model(), c.offset, frame, camera, sun));
  c.luts->run_all(c.plan, jobs);
  c.frame = make_sky_frame(*c.luts, c.plan, camera, c.offset, illuminance);
}

Camera path_camera(int frame, double altitude, float aspect) {
  const double t = double(frame);
  const glm::dvec3 pos(t * 3.0, altitude + t * 0.5, t * 1.0);
  const double yaw = t * 0.2 * kPiD / 180.0;
  return Camera::look_at(pos, pos + glm::dvec3(std::cos(yaw), -0.05, std::sin(yaw)), 1.0471976f, aspect, 0.1f);
}

glm::vec3 path_sun(int frame) {
  const double elev = (30.0 - double(frame) * 0.1) * kPiD / 180.0;
  return glm::normalize(glm::vec3(float(std::cos(elev) * 0.8), float(std::sin(elev)), float(std::cos(elev) * 0.6)));
}

Camera horizon_camera(double altitude, int width, int height) {
  return Camera::look_at(glm::dvec3(0.0, altitude, 0.0), glm::dvec3(1000.0, altitude, 0.0), 1.0471976f,
                         float(width) / float(height), 0.1f);
}

glm::vec3 solar_sun_illuminance() { return glm::vec3(solar_color() * solar_illuminance_lux()); }

glm::vec3 sun_at_zenith_angle(double zenith_deg) {
  const double z = zenith_deg * kPiD / 180.0;
  return glm::vec3(float(std::sin(z)), float(std::cos(z)), 0.0f);
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace cr
