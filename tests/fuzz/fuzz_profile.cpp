// libFuzzer target: profile JSON -> cr::load_profile with the built-in
// plugins' sections ("atmosphere", "fog"), then those sections through the
// plugins' own validation as their configure() runs it
// (parse_atmosphere_settings, also for an absent section, and
// parse_fog_profile). The bytes are written to <scratch>/profile.json.
#include <string>
#include <vector>

#include "atmosphere/atmosphere_settings.h"
#include "engine/core/profile.h"
#include "fog/fog_settings.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

const std::vector<std::string> kPluginSections = {"atmosphere", "fog"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cr::fuzz::write_scratch_file("profile.json", data, size);
  cr::fuzz::run_one("profile", [&] {
    const cr::Profile p = cr::load_profile(path, kPluginSections);
    auto atmosphere = p.plugins.find("atmosphere");
    (void)cr::parse_atmosphere_settings(atmosphere == p.plugins.end() ? nlohmann::json() : *atmosphere, p.path);
    if (p.plugins.contains("fog")) (void)cr::parse_fog_profile(p.plugins.at("fog"), p.path);
  });
  return 0;
}
