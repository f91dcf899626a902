#include "atmosphere/config_fields.h"

#include <cmath>

#include "engine/core/error.h"

namespace cr {

ConfigFields::ConfigFields(const nlohmann::json& object, std::string file, std::string prefix)
    : object_(object.is_null() ? nlohmann::json::object() : object),
      file_(std::move(file)),
      prefix_(std::move(prefix)) {
  if (!object_.is_object()) throw InputError(file_, prefix_ + ": must be a JSON object");
}

void ConfigFields::fail(const std::string& key, const std::string& what) const {
  throw InputError(file_, prefix_ + "." + key + ": " + what);
}

bool ConfigFields::has(const std::string& key) const { return object_.contains(key); }

const nlohmann::json* ConfigFields::find(const std::string& key) {
  used_.insert(key);
  auto it = object_.find(key);
  return it == object_.end() ? nullptr : &*it;
}

double ConfigFields::number(const std::string& key, double fallback, double lo, double hi) {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_number()) fail(key, "must be a number");
  const double x = v->get<double>();
  if (!std::isfinite(x) || x < lo || x > hi)
    fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v->dump());
  return x;
}

int ConfigFields::integer(const std::string& key, int fallback, int lo, int hi) {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_number_integer()) fail(key, "must be an integer");
  const long long x = v->get<long long>();
  if (x < lo || x > hi)
    fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v->dump());
  return int(x);
}

bool ConfigFields::boolean(const std::string& key, bool fallback) {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_boolean()) fail(key, "must be true or false");
  return v->get<bool>();
}

std::string ConfigFields::text(const std::string& key, const std::string& fallback) {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_string()) fail(key, "must be a string");
  return v->get<std::string>();
}

glm::vec3 ConfigFields::color(const std::string& key, const glm::vec3& fallback, float lo, float hi) {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  glm::vec3 c;
  if (v->is_number()) {
    c = glm::vec3(v->get<float>());
  } else if (v->is_array() && v->size() == 3 && (*v)[0].is_number() && (*v)[1].is_number() &&
             (*v)[2].is_number()) {
    c = glm::vec3((*v)[0].get<float>(), (*v)[1].get<float>(), (*v)[2].get<float>());
  } else {
    fail(key, "must be a number or an array of 3 numbers");
  }
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(c[i]) || c[i] < lo || c[i] > hi)
      fail(key, "components must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                    v->dump());
  return c;
}

ConfigFields ConfigFields::object(const std::string& key) {
  const nlohmann::json* v = find(key);
  if (v && !v->is_object()) fail(key, "must be a JSON object");
  return ConfigFields(v ? *v : nlohmann::json(), file_, prefix_ + "." + key);
}

void ConfigFields::finish() const {
  for (auto it = object_.begin(); it != object_.end(); ++it)
    if (!used_.count(it.key())) fail(it.key(), "unknown key");
}

}  // namespace cr
