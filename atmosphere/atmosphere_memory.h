#pragma once
// What the atmosphere's LUTs and environment take, charged to a run's
// MemoryBudget before any is built (engine/core/memory_budget.h).
#include <string>

#include "atmosphere/atmosphere_settings.h"
#include "engine/core/memory_budget.h"

namespace cr {

void estimate_atmosphere_memory(const AtmosphereSettings& settings, const std::string& profile_path,
                                MemoryBudget& memory);

}  // namespace cr
