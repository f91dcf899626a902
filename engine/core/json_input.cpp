#include "engine/core/json_input.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/json_builder.h"

namespace cr {

namespace {

// Input files are small; anything larger is not a profile or scene file.
constexpr std::streamoff kMaxJsonFileBytes = 64ll << 20;

std::string type_name(const nlohmann::json& v) { return v.type_name(); }

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

nlohmann::json load_json_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a directory, not a JSON file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  if (size < 0) throw InputError(path, "cannot read file");
  if (size > kMaxJsonFileBytes) {
    throw InputError(path, "file is " + std::to_string(size) + " bytes; a JSON input is limited to " +
                               std::to_string(kMaxJsonFileBytes) + " bytes");
  }
  in.seekg(0, std::ios::beg);
  std::string text(static_cast<size_t>(size), '\0');
  if (!in.read(text.data(), size)) throw InputError(path, "cannot read file");
  // nlohmann keeps the last of repeated keys silently; a repeated key in an
  // input file is almost always an editing mistake, so it is an error.
  JsonBuildOptions options;
  options.reject_duplicate_keys = true;
  return build_json(text.data(), text.data() + text.size(), path, options);
}

void check_json_depth(const std::string& path, int depth, nlohmann::json::parse_event_t event) {
  using Event = nlohmann::json::parse_event_t;
  if ((event == Event::object_start || event == Event::array_start) && depth >= kMaxJsonDepth)
    throw InputError(path, "JSON nests arrays and objects more than " + std::to_string(kMaxJsonDepth) +
                               " levels deep");
}

bool NumberRange::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (min_exclusive ? !(v > min) : !(v >= min)) return false;
  if (max_exclusive ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string NumberRange::describe() const {
  bool unbounded_above = std::isinf(max);
  std::string s = "a finite number ";
  if (unbounded_above) return s + (min_exclusive ? "> " : ">= ") + format_number(min);
  return s + "in " + (min_exclusive ? "(" : "[") + format_number(min) + ", " + format_number(max) +
         (max_exclusive ? ")" : "]");
}

JsonObject::JsonObject(const nlohmann::json& value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {
  if (!value_.is_object()) {
    throw InputError(file_, (path_.empty() ? std::string("the document") : "'" + path_ + "'") +
                                " must be a JSON object, found " + type_name(value_));
  }
}

std::string JsonObject::field(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

std::vector<std::string> JsonObject::keys() const {
  std::vector<std::string> out;
  for (auto it = value_.begin(); it != value_.end(); ++it) out.push_back(it.key());
  return out;
}

void JsonObject::allow_only(std::initializer_list<const char*> allowed) const {
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || it.key() == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      throw InputError(file_, "unknown key '" + field(it.key()) + "' (allowed here: " + list + ")");
    }
  }
}

void JsonObject::fail(const std::string& key, const std::string& what) const {
  throw InputError(file_, "'" + field(key) + "' " + what);
}

const nlohmann::json& JsonObject::member(const char* key) const {
  auto it = value_.find(key);
  if (it == value_.end()) fail(key, "is required");
  return *it;
}

double JsonObject::number(const char* key, const NumberRange& range) const {
  const nlohmann::json& v = member(key);
  if (!v.is_number()) fail(key, "must be a number, found " + type_name(v));
  double d = v.get<double>();
  if (!range.contains(d)) fail(key, "must be " + range.describe() + ", found " + format_number(d));
  return d;
}

int JsonObject::integer(const char* key, long long min, long long max) const {
  const nlohmann::json& v = member(key);
  std::string expect = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (!v.is_number()) fail(key, "must be " + expect + ", found " + type_name(v));
  double d = v.get<double>();
  if (!std::isfinite(d) || d != std::floor(d) || d < static_cast<double>(min) || d > static_cast<double>(max)) {
    fail(key, "must be " + expect + ", found " + v.dump());
  }
  return static_cast<int>(d);
}

bool JsonObject::boolean(const char* key) const {
  const nlohmann::json& v = member(key);
  if (!v.is_boolean()) fail(key, "must be true or false, found " + type_name(v));
  return v.get<bool>();
}

std::string JsonObject::string(const char* key) const {
  const nlohmann::json& v = member(key);
  if (!v.is_string()) fail(key, "must be a string, found " + type_name(v));
  return v.get<std::string>();
}

std::vector<double> JsonObject::numbers(const char* key, size_t n, const NumberRange& range) const {
  const nlohmann::json& v = member(key);
  std::string expect = "an array of " + std::to_string(n) + " numbers";
  if (!v.is_array() || v.size() != n) fail(key, "must be " + expect + ", found " + v.dump());
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) {
    if (!v[i].is_number()) fail(key, "must be " + expect + ", found " + v.dump());
    double d = v[i].get<double>();
    if (!range.contains(d)) {
      fail(key, "element " + std::to_string(i) + " must be " + range.describe() + ", found " + format_number(d));
    }
    out.push_back(d);
  }
  return out;
}

glm::dvec3 JsonObject::vec3(const char* key, const NumberRange& range) const {
  std::vector<double> v = numbers(key, 3, range);
  return {v[0], v[1], v[2]};
}

JsonObject JsonObject::object(const char* key) const { return JsonObject(member(key), file_, field(key)); }

std::vector<JsonObject> JsonObject::objects(const char* key) const {
  const nlohmann::json& v = member(key);
  if (!v.is_array() || v.empty()) fail(key, "must be a non-empty array of objects, found " + type_name(v));
  std::vector<JsonObject> out;
  for (size_t i = 0; i < v.size(); ++i) out.emplace_back(v[i], file_, field(key) + "[" + std::to_string(i) + "]");
  return out;
}

}  // namespace cr
