#include "engine/cli/module_truth.h"

#include "engine/core/error.h"

namespace cr {

void ModuleTruthRegistry::add(ModuleTruth truth) {
  if (find(truth.module)) throw Error("module truth '" + truth.module + "' registered twice");
  truths_.push_back(std::move(truth));
}

const ModuleTruth* ModuleTruthRegistry::find(const std::string& module) const {
  for (const ModuleTruth& t : truths_)
    if (t.module == module) return &t;
  return nullptr;
}

}  // namespace cr
