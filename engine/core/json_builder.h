#pragma once
// Builds a nlohmann::json document from untrusted JSON text in one pass
// (nlohmann's SAX interface), refusing nesting deeper than kMaxJsonDepth and,
// optionally, keys repeated in one object, and reporting the value count as
// it grows (for memory budgets). nlohmann's parse callback could check the
// same, but it rescans the parent container at every object's end, which
// makes parsing quadratic in the number of objects (100k objects: 19 s).
#include <cstddef>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

namespace cr {

struct JsonBuildOptions {
  std::string label = "JSON";          // in messages: "malformed <label>: ..."
  bool reject_duplicate_keys = false;  // InputError "key 'k' appears twice in one object"
  // Called with the number of values so far, every `check_every` values; may throw.
  std::function<void(size_t values)> on_values;
  size_t check_every = 65536;
};

// Throws InputError(path, ...) for malformed text (with the parser's line and
// column), too deep nesting and, if asked, repeated keys. `values` (optional)
// receives the number of values in the document.
nlohmann::json build_json(const char* begin, const char* end, const std::string& path,
                          const JsonBuildOptions& options = {}, size_t* values = nullptr);

}  // namespace cr
