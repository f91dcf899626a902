// One-pass JSON building for untrusted files: the same document as
// nlohmann::json::parse, repeated keys refused where asked, value counts
// reported as they grow, and time linear in the number of objects (nlohmann's
// parse callback made 100k objects take 19 s).
#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include "engine/core/error.h"
#include "engine/core/json_builder.h"

namespace {

nlohmann::json build(const std::string& text, const cr::JsonBuildOptions& o = {}, size_t* values = nullptr) {
  return cr::build_json(text.data(), text.data() + text.size(), "f.json", o, values);
}

std::string error_of(const std::string& text, const cr::JsonBuildOptions& o = {}) {
  try {
    build(text, o);
  } catch (const cr::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("JSON builder: the document equals nlohmann's parse, and values are counted") {
  const std::string text = R"({"a": [1, 2.5, -3, true, null, "s", {"b": {}}], "c": {"d": [[], [1e3]]}, "e": 18446744073709551615})";
  size_t values = 0;
  CHECK(build(text, {}, &values) == nlohmann::json::parse(text));
  CHECK(values == 16);
  CHECK(build("7") == 7);
}

TEST_CASE("JSON builder: repeated keys are refused where asked; malformed text names file and position") {
  cr::JsonBuildOptions strict;
  strict.reject_duplicate_keys = true;
  CHECK(error_of(R"({"a": 1, "b": {"a": 2, "a": 3}})", strict) == "f.json: key 'a' appears twice in one object");
  CHECK(build(R"({"a": 1, "a": 2})")["a"] == 2);  // otherwise the last value wins, as in nlohmann's parse
  CHECK(error_of(R"({"a": 1,})").find("f.json: malformed JSON: ") == 0);
  CHECK(error_of(R"({"a": 1e999})").find("malformed JSON") != std::string::npos);
  cr::JsonBuildOptions label;
  label.label = "glTF JSON";
  CHECK(error_of("[", label).find("f.json: malformed glTF JSON: ") == 0);
}

TEST_CASE("JSON builder: the value callback sees the count grow and may stop the parse") {
  cr::JsonBuildOptions o;
  o.check_every = 10;
  size_t last = 0;
  o.on_values = [&](size_t n) {
    CHECK(n == last + 10);
    last = n;
    if (n >= 50) throw cr::InputError("f.json", "too many values");
  };
  std::string text = "[";
  for (int i = 0; i < 1000; ++i) text += std::to_string(i) + ",";
  text += "0]";
  CHECK(error_of(text, o) == "f.json: too many values");
  CHECK(last == 50);
}

TEST_CASE("JSON builder: 200,000 objects in one array parse in linear time") {
  std::string text = "[";
  for (int i = 0; i < 200000; ++i) text += R"({"k": 1},)";
  text += "{}]";
  cr::JsonBuildOptions strict;
  strict.reject_duplicate_keys = true;
  const auto t0 = std::chrono::steady_clock::now();
  const nlohmann::json doc = build(text, strict);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(doc.size() == 200001);
  MESSAGE("200k objects: " << s << " s");
  CHECK(s < 10.0);  // quadratic: about 75 s in a release build
}
