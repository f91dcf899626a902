#pragma once
// A sweep's table (OUT/sweep.csv) from its document (OUT/sweep.json): one row
// per point with its settings, frame-time percentiles, errors, module errors
// and every pass's p50/p95/mean.
#include <string>

#include <nlohmann/json.hpp>

namespace cr {

std::string sweep_csv(const nlohmann::json& doc);

}  // namespace cr
