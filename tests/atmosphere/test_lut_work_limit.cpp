// A profile cannot ask for a LUT rebuild of minutes: each LUT's march steps
// per rebuild (texels x steps, x directions and orders for multiscattering)
// stay within 2^28, and the per-pixel space march within 256 steps.
#include <doctest/doctest.h>

#include <string>

#include "atmosphere/atmosphere_settings.h"
#include "engine/core/error.h"

using namespace cr;

namespace {

std::string message(const nlohmann::json& section) {
  try {
    (void)parse_atmosphere_settings(section, "p.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("LUT work limit: rebuilds beyond 2^28 march steps are refused naming the LUT's field") {
  CHECK(message({{"transmittance_lut", {{"width", 4096}, {"height", 4096}, {"steps", 4096}}}}) ==
        "p.json: atmosphere.transmittance_lut.steps: width x height x steps march 6.87e+10 steps per rebuild, more "
        "than the limit of 2.68e+08");
  CHECK(message({{"skyview_lut", {{"width", 4096}, {"height", 4096}, {"max_steps", 1024}}}})
            .find("atmosphere.skyview_lut.max_steps: width x height x max_steps march 1.72e+10") != std::string::npos);
  CHECK(message({{"multiscattering_lut", {{"width", 1024}, {"height", 1024}, {"directions", 4096}}}})
            .find("atmosphere.multiscattering_lut.steps") != std::string::npos);
  CHECK(message({{"aerial_perspective_lut", {{"width", 512}, {"height", 512}, {"depth", 512}, {"steps_per_slice", 64}}}})
            .find("atmosphere.aerial_perspective_lut.steps_per_slice") != std::string::npos);
  CHECK(message({{"space_march_steps", 257}}).find("atmosphere.space_march_steps") != std::string::npos);
  // The limit itself passes: 4096 x 1024 x 64 = 2^28 transmittance steps.
  CHECK(message({{"transmittance_lut", {{"width", 4096}, {"height", 1024}, {"steps", 64}}}}).empty());
  CHECK(message({{"transmittance_lut", {{"width", 4096}, {"height", 1024}, {"steps", 65}}}}) != "");
  CHECK(message(nlohmann::json()).empty());  // the desktop defaults
}
