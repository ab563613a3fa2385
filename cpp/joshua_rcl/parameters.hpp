// Typed read access to the parameters given as `--ros-args -p name:=value`, as parsed by rcl.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rcl_yaml_param_parser/types.h"

namespace joshua {

// Parameter overrides of one node. A value of the wrong type is a SettingsError (exit code 2);
// an absent one gives the default.
class Parameters {
 public:
  // Takes ownership of `overrides` (may be null: no parameters). `node_fqn` is e.g. "/leader".
  Parameters(rcl_params_t* overrides, std::string node_fqn);
  ~Parameters();
  Parameters(const Parameters&) = delete;
  Parameters& operator=(const Parameters&) = delete;

  bool has(const std::string& name) const;
  std::string get_string(const std::string& name, const std::string& fallback = "") const;
  // A string that must be present and non-empty.
  std::string require_string(const std::string& name) const;
  int64_t get_int(const std::string& name, int64_t fallback = 0) const;
  // Integers are accepted too (`rate_hz:=100`).
  double get_double(const std::string& name, double fallback = 0.0) const;
  bool get_bool(const std::string& name, bool fallback = false) const;
  std::vector<int64_t> get_int_array(const std::string& name) const;
  std::vector<std::string> get_string_array(const std::string& name) const;

 private:
  const rcl_variant_t* find(const std::string& name) const;
  [[noreturn]] void wrong_type(const std::string& name, const char* expected) const;

  rcl_params_t* overrides_;
  std::string node_fqn_;
};

}  // namespace joshua
