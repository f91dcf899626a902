#include "engine/cli/sweep_points.h"

#include <algorithm>
#include <set>

#include "engine/cli/arg_parser.h"
#include "engine/core/error.h"
#include "engine/core/profile_keys.h"

namespace cr {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  size_t begin = 0;
  while (true) {
    const size_t end = text.find(separator, begin);
    parts.push_back(text.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) return parts;
    begin = end + 1;
  }
}

nlohmann::json parse_value(const std::string& key, const std::string& token, const std::string& axis) {
  if (token.empty()) throw UsageError("--axis " + axis + ": an empty value");
  if (key == "resolution") {
    const size_t x = token.find('x');
    int w = 0, h = 0;
    try {
      size_t used_w = 0, used_h = 0;
      if (x != std::string::npos) {
        w = std::stoi(token.substr(0, x), &used_w);
        h = std::stoi(token.substr(x + 1), &used_h);
      }
      if (x == std::string::npos || used_w != x || used_h != token.size() - x - 1) w = 0;
    } catch (const std::exception&) {
      w = 0;
    }
    if (w < 1 || h < 1) throw UsageError("--axis " + axis + ": '" + token + "' is not WxH, e.g. 960x540");
    return nlohmann::json::array({w, h});
  }
  const nlohmann::json value = nlohmann::json::parse(token, nullptr, false);
  if (!value.is_discarded() && (value.is_number() || value.is_boolean())) return value;
  return token;
}

}  // namespace

SweepAxis parse_sweep_axis(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError("--axis '" + text + "': expected KEY=V1,V2,... (e.g. atmosphere.spectral_samples=3,6)");
  SweepAxis axis;
  axis.key = text.substr(0, eq);
  for (const std::string& key_part : split(axis.key, '.'))
    if (key_part.empty()) throw UsageError("--axis '" + text + "': an empty key component");
  std::set<std::string> seen;
  for (const std::string& token : split(text.substr(eq + 1), ',')) {
    if (!seen.insert(token).second) throw UsageError("--axis '" + text + "': the value '" + token + "' twice");
    axis.values.push_back(parse_value(axis.key, token, text));
  }
  return axis;
}

std::string SweepPoint::id() const {
  if (!label.empty()) return label;
  std::string out;
  for (const auto& [key, value] : settings) {
    if (!out.empty()) out += ';';
    out += key + '=' + (value.is_string() ? value.get<std::string>() : value.dump());
  }
  return out;
}

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes) {
  std::set<std::string> keys;
  for (const SweepAxis& a : axes)
    if (!keys.insert(a.key).second) throw UsageError("--axis " + a.key + ": given twice");
  std::vector<SweepPoint> points(1);
  for (const SweepAxis& a : axes) {
    std::vector<SweepPoint> next;
    for (const SweepPoint& p : points)
      for (const nlohmann::json& v : a.values) {
        SweepPoint q = p;
        q.settings.emplace_back(a.key, v);
        next.push_back(std::move(q));
      }
    points = std::move(next);
  }
  return axes.empty() ? std::vector<SweepPoint>{} : points;
}

SweepPoint parse_listed_point(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size() || text.find_first_of(";=", eq + 1) != std::string::npos ||
      text.substr(0, eq).find(';') != std::string::npos)
    throw UsageError("--point '" + text + "': expected LABEL=PROFILE (e.g. mobile=mobile, auto=auto)");
  SweepPoint p;
  p.label = text.substr(0, eq);
  p.profile = text.substr(eq + 1);
  return p;
}

SweepFile parse_sweep_file(const nlohmann::json& doc, const std::string& path) {
  if (!doc.is_object()) throw InputError(path, "a sweep file is a JSON object");
  for (const auto& [key, value] : doc.items())
    if (key != "axes" && key != "points") throw InputError(path, "unknown key '" + key + "' (axes, points)");
  SweepFile f;
  if (doc.contains("axes")) {
    if (!doc["axes"].is_object()) throw InputError(path, "axes: expected an object of KEY: [values]");
    for (const auto& [key, values] : doc["axes"].items()) {
      if (!values.is_array() || values.empty()) throw InputError(path, "axes." + key + ": expected a non-empty array");
      SweepAxis a;
      a.key = key;
      for (const nlohmann::json& v : values) {
        if (std::find(a.values.begin(), a.values.end(), v) != a.values.end())
          throw InputError(path, "axes." + key + ": the value " + v.dump() + " twice");
        a.values.push_back(v);
      }
      f.axes.push_back(std::move(a));
    }
  }
  if (doc.contains("points")) {
    if (!doc["points"].is_array()) throw InputError(path, "points: expected an array");
    for (size_t i = 0; i < doc["points"].size(); ++i) {
      const nlohmann::json& q = doc["points"][i];
      const std::string at = "points[" + std::to_string(i) + "]";
      if (!q.is_object() || !q.contains("label") || !q["label"].is_string() || q["label"].get<std::string>().empty())
        throw InputError(path, at + ": expected an object with a \"label\"");
      SweepPoint p;
      p.label = q["label"].get<std::string>();
      for (const auto& [key, value] : q.items()) {
        if (key == "label") continue;
        if (key == "profile" && value.is_string()) p.profile = value.get<std::string>();
        else if (key == "settings" && value.is_object())
          for (const auto& [k, v] : value.items()) p.settings.emplace_back(k, v);
        else throw InputError(path, at + "." + key + ": expected \"profile\" (a string) or \"settings\" (an object)");
      }
      f.points.push_back(std::move(p));
    }
  }
  return f;
}

nlohmann::json apply_sweep_point(nlohmann::json profile, const SweepPoint& point) {
  for (const auto& [key, value] : point.settings)
    if (key != "threads") set_profile_key(profile, key, value);
  return profile;
}

unsigned sweep_point_threads(const SweepPoint& point, unsigned otherwise) {
  for (const auto& [key, value] : point.settings)
    if (key == "threads") {
      if (!value.is_number_integer() || value.get<int>() < 1 || value.get<int>() > 1024)
        throw UsageError("--axis threads: values must be integers in [1, 1024]");
      return unsigned(value.get<int>());
    }
  return otherwise;
}

}  // namespace cr
