#pragma once
// Strict reading of JSON input files (profiles, scene files, plugin sections).
// Every accessor checks type and range and throws InputError naming the file
// and the full field path ("camera.keys[2].vfov_deg"), so one bad value gives
// one clear message. Unknown keys are errors, never silently ignored.
#include <initializer_list>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace cr {

// Deepest nesting of arrays and objects an input may have. Deeper documents
// are refused while parsing: code that walks a document recursively (copies,
// tinygltf's conversion of extras) would otherwise overflow the stack.
inline constexpr int kMaxJsonDepth = 128;

// Reads and parses a JSON file; a syntax error reports the parser's position.
nlohmann::json load_json_file(const std::string& path);

// Throws InputError(path, ...) when a parse callback's event opens an array or
// object below kMaxJsonDepth levels: call it from every parse callback.
void check_json_depth(const std::string& path, int depth, nlohmann::json::parse_event_t event);

// An inclusive or exclusive interval for numeric fields; always finite-only.
struct NumberRange {
  double min;
  double max;
  bool min_exclusive = false;
  bool max_exclusive = false;
  bool contains(double v) const;
  std::string describe() const;  // e.g. "in (0, 180)"
};

// A JSON object being validated: `path` is its own field path ("" for the root).
class JsonObject {
 public:
  JsonObject(const nlohmann::json& value, std::string file, std::string path);

  const nlohmann::json& json() const { return value_; }
  const std::string& file() const { return file_; }
  std::string field(const std::string& key) const;  // full path of a member
  bool has(const char* key) const { return value_.contains(key); }
  std::vector<std::string> keys() const;

  // Throws naming the first key not in `allowed`.
  void allow_only(std::initializer_list<const char*> allowed) const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  double number(const char* key, const NumberRange& range) const;
  int integer(const char* key, long long min, long long max) const;
  bool boolean(const char* key) const;
  std::string string(const char* key) const;
  // An array of exactly `n` numbers in range.
  std::vector<double> numbers(const char* key, size_t n, const NumberRange& range) const;
  glm::dvec3 vec3(const char* key, const NumberRange& range) const;
  JsonObject object(const char* key) const;
  // A non-empty array of objects, each addressed as "key[i]".
  std::vector<JsonObject> objects(const char* key) const;

 private:
  const nlohmann::json& member(const char* key) const;

  const nlohmann::json& value_;
  std::string file_;
  std::string path_;
};

}  // namespace cr
