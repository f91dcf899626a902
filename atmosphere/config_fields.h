#pragma once
// Reads one JSON object of a scene or profile section field by field, with
// ranges and defaults, and rejects keys nobody asked for. Every error is an
// InputError naming the file and the dotted field ("atmosphere.skyview_lut.width").
#include <set>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace cr {

class ConfigFields {
 public:
  // `object` may be null (an absent section: every field takes its default).
  ConfigFields(const nlohmann::json& object, std::string file, std::string prefix);

  bool has(const std::string& key) const;
  double number(const std::string& key, double fallback, double lo, double hi);
  int integer(const std::string& key, int fallback, int lo, int hi);
  bool boolean(const std::string& key, bool fallback);
  std::string text(const std::string& key, const std::string& fallback);
  // A scalar (grey) or an [r, g, b] array, each component in [lo, hi].
  glm::vec3 color(const std::string& key, const glm::vec3& fallback, float lo, float hi);
  // A nested object (absent: an empty reader, so its fields take defaults).
  ConfigFields object(const std::string& key);
  // Throws on the first key that no getter asked for.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  const std::string& file() const { return file_; }

 private:
  const nlohmann::json* find(const std::string& key);
  nlohmann::json object_;
  std::string file_;
  std::string prefix_;
  std::set<std::string> used_;
};

}  // namespace cr
