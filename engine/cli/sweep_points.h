#pragma once
// The points of a settings sweep: axes of profile keys and their values
// ("atmosphere.skyview_lut.width=96,192,384"), their cross product, and a
// point applied to a profile document. A key is a dotted path into the
// profile JSON; two keys are not profile keys: "threads" (the run's worker
// threads) and "resolution" (values WxH).
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace cr {

struct SweepAxis {
  std::string key;
  std::vector<nlohmann::json> values;
};

// "KEY=V1,V2,...": each value is JSON when it parses as a scalar (numbers,
// true, false) and a string otherwise ("msaa4"); "resolution" values are WxH.
// Throws UsageError naming the axis when malformed (no '=', an empty key or
// value, a repeated value).
SweepAxis parse_sweep_axis(const std::string& text);

struct SweepPoint {
  // A listed point's name ("desktop", "auto"); empty for a point of the axes.
  std::string label;
  // The profile it starts from (a name, a file, or auto[:BASE]); empty: the sweep's base.
  std::string profile;
  std::vector<std::pair<std::string, nlohmann::json>> settings;  // in axis order
  // The label, else "key=value;key=value": names the point in outputs and for --resume.
  std::string id() const;
};

// "LABEL=PROFILE" (--point): a listed point rendering that profile as it is.
// UsageError when malformed.
SweepPoint parse_listed_point(const std::string& text);

// A sweep file: {"axes": {"KEY": [V1, V2, ...], ...}, "points": [{"label":
// "L", "profile": "P", "settings": {"KEY": V, ...}}, ...]}, both optional.
// Axes keep the file's key order. InputError naming the file and field.
struct SweepFile {
  std::vector<SweepAxis> axes;
  std::vector<SweepPoint> points;
};
SweepFile parse_sweep_file(const nlohmann::json& doc, const std::string& path);

// The cross product of the axes, the first axis varying slowest. Throws
// UsageError when two axes name the same key.
std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes);

// The profile document with the point's profile keys set (objects on the
// path are created; "threads" is not a profile key and is left out). The
// result is validated where it is loaded, like any profile file.
nlohmann::json apply_sweep_point(nlohmann::json profile, const SweepPoint& point);

// The point's "threads" setting, or `otherwise`.
unsigned sweep_point_threads(const SweepPoint& point, unsigned otherwise);

}  // namespace cr
