#pragma once
// The timing of one frame: what the renderer records and the reports and the
// trace read (one definition for both, so nothing is copied field by field).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/job_system.h"

namespace cr {

struct PassTiming {
  std::string name;
  double begin_us = 0.0;  // job-system clock
  double end_us = 0.0;
  double ms() const { return (end_us - begin_us) * 1e-3; }
};

struct FrameTiming {
  int frame = 0;
  double begin_us = 0.0;              // job-system clock at frame start
  double frame_ms = 0.0;              // wall time of the frame
  std::vector<PassTiming> passes;     // executed passes, declaration order
  std::vector<std::string> culled;    // passes the frame graph removed
  std::vector<JobRecord> jobs;        // every job of the frame
  nlohmann::json plugins = nlohmann::json::object();  // plugin entries by plugin name
};

}  // namespace cr
