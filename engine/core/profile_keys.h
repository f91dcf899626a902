#pragma once
// Profile keys written as dotted paths into the profile JSON
// ("atmosphere.skyview_lut.width"): what sweeps vary and the `auto` planner
// sets.
#include <string>

#include <nlohmann/json.hpp>

namespace cr {

// Sets `key` in `profile`, creating the objects on its path. Throws
// InputError naming the key when a component on the path is not an object.
// The result is validated where it is loaded, like any profile file.
void set_profile_key(nlohmann::json& profile, const std::string& key, const nlohmann::json& value);

// The value at `key`, or null where the path does not exist.
nlohmann::json profile_key(const nlohmann::json& profile, const std::string& key);

}  // namespace cr
