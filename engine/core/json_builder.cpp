#include "engine/core/json_builder.h"

#include <vector>

#include "engine/core/error.h"
#include "engine/core/json_input.h"

namespace cr {

namespace {

class JsonBuilder final : public nlohmann::json_sax<nlohmann::json> {
 public:
  JsonBuilder(const std::string& path, const JsonBuildOptions& options) : path_(path), options_(options) {}

  nlohmann::json document;
  size_t values() const { return values_; }

  bool null() override { return add(nullptr); }
  bool boolean(bool v) override { return add(v); }
  bool number_integer(number_integer_t v) override { return add(v); }
  bool number_unsigned(number_unsigned_t v) override { return add(v); }
  bool number_float(number_float_t v, const string_t&) override { return add(v); }
  bool string(string_t& v) override { return add(std::move(v)); }
  bool binary(binary_t& v) override { return add(nlohmann::json::binary(std::move(v))); }  // not in JSON text
  bool start_object(std::size_t) override {
    return open(nlohmann::json::object(), nlohmann::json::parse_event_t::object_start);
  }
  bool key(string_t& k) override {
    if (options_.reject_duplicate_keys && open_.back()->contains(k))
      throw InputError(path_, "key '" + k + "' appears twice in one object");
    key_ = std::move(k);
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override {
    return open(nlohmann::json::array(), nlohmann::json::parse_event_t::array_start);
  }
  bool end_array() override { return close(); }
  // Syntax errors and numbers beyond double (1e999); the text carries the position.
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    throw InputError(path_, "malformed " + options_.label + ": " + e.what());
  }

 private:
  // Places `v` in the innermost open container (or as the document) and returns where it went.
  nlohmann::json& place(nlohmann::json&& v) {
    if (++values_ % options_.check_every == 0 && options_.on_values) options_.on_values(values_);
    if (open_.empty()) return document = std::move(v);
    nlohmann::json& parent = *open_.back();
    if (parent.is_array()) {
      parent.push_back(std::move(v));
      return parent.back();
    }
    return parent[key_] = std::move(v);  // a repeated key keeps the last value, as nlohmann's parse does
  }
  bool add(nlohmann::json&& v) {
    place(std::move(v));
    return true;
  }
  bool open(nlohmann::json&& container, nlohmann::json::parse_event_t event) {
    check_json_depth(path_, static_cast<int>(open_.size()), event);
    // Only the innermost container grows, so pointers to the open ones stay valid.
    open_.push_back(&place(std::move(container)));
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  const std::string& path_;
  const JsonBuildOptions& options_;
  std::vector<nlohmann::json*> open_;
  std::string key_;
  size_t values_ = 0;
};

}  // namespace

nlohmann::json build_json(const char* begin, const char* end, const std::string& path,
                          const JsonBuildOptions& options, size_t* values) {
  JsonBuilder builder(path, options);
  nlohmann::json::sax_parse(begin, end, &builder);
  if (values) *values = builder.values();
  return std::move(builder.document);
}

}  // namespace cr
