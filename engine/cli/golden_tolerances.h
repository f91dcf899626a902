#pragma once
// Per-profile comparison thresholds of the golden run (tests/golden/tolerances.json).
// Each entry must state every threshold and, in "why", the reason for each
// value: a tolerance nobody can explain cannot be reviewed.
//
// {
//   "comment": "...",
//   "profiles": {
//     "default": {"max_abs": 0.5, "rmse": 0.004, "pixel_threshold": 0.0079,
//                 "max_fraction": 0.002, "flip_mean": 0.005,
//                 "why": {"max_abs": "...", "rmse": "...", ...}},
//     "desktop": {...}
//   }
// }
// A profile without its own entry uses "default" (required).
#include <map>
#include <string>

#include "engine/output/image_compare.h"

namespace cr {

struct GoldenTolerance {
  std::string entry;  // the entry used: the profile's name or "default"
  CompareThresholds thresholds;
};

class GoldenTolerances {
 public:
  // Throws InputError naming the file and field for anything missing or wrong.
  static GoldenTolerances load(const std::string& path);

  GoldenTolerance for_profile(const std::string& profile) const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::map<std::string, CompareThresholds> entries_;
};

}  // namespace cr
