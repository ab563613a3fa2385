// Typed lookups in rcl's parameter overrides: the node's own entry wins over the `/**` wildcard.
#include "joshua_rcl/parameters.hpp"

#include <utility>

#include "joshua_rcl/errors.hpp"
#include "rcl_yaml_param_parser/parser.h"

namespace joshua {
namespace {

const char* const WILDCARD_NODES[] = {"/**", "/*"};

const rcl_variant_t* find_in(const rcl_node_params_t& node, const std::string& name) {
  for (size_t i = 0; i < node.num_params; ++i) {
    if (name == node.parameter_names[i]) return &node.parameter_values[i];
  }
  return nullptr;
}

}  // namespace

Parameters::Parameters(rcl_params_t* overrides, std::string node_fqn)
    : overrides_(overrides), node_fqn_(std::move(node_fqn)) {}

Parameters::~Parameters() {
  if (overrides_ != nullptr) rcl_yaml_node_struct_fini(overrides_);
}

const rcl_variant_t* Parameters::find(const std::string& name) const {
  if (overrides_ == nullptr) return nullptr;
  const rcl_variant_t* wildcard = nullptr;
  for (size_t i = 0; i < overrides_->num_nodes; ++i) {
    const std::string node = overrides_->node_names[i];
    const std::string qualified = node.empty() || node[0] == '/' ? node : "/" + node;
    if (qualified == node_fqn_) {
      if (const rcl_variant_t* value = find_in(overrides_->params[i], name)) return value;
    }
    for (const char* pattern : WILDCARD_NODES) {
      if (qualified == pattern && wildcard == nullptr) wildcard = find_in(overrides_->params[i], name);
    }
  }
  return wildcard;
}

void Parameters::wrong_type(const std::string& name, const char* expected) const {
  throw SettingsError("parameter " + name + " must be " + expected);
}

bool Parameters::has(const std::string& name) const { return find(name) != nullptr; }

std::string Parameters::get_string(const std::string& name, const std::string& fallback) const {
  const rcl_variant_t* value = find(name);
  if (value == nullptr) return fallback;
  if (value->string_value == nullptr) wrong_type(name, "a string");
  return value->string_value;
}

std::string Parameters::require_string(const std::string& name) const {
  std::string value = get_string(name);
  if (value.empty()) throw SettingsError("parameter " + name + " is required");
  return value;
}

int64_t Parameters::get_int(const std::string& name, int64_t fallback) const {
  const rcl_variant_t* value = find(name);
  if (value == nullptr) return fallback;
  if (value->integer_value == nullptr) wrong_type(name, "an integer");
  return *value->integer_value;
}

double Parameters::get_double(const std::string& name, double fallback) const {
  const rcl_variant_t* value = find(name);
  if (value == nullptr) return fallback;
  if (value->double_value != nullptr) return *value->double_value;
  if (value->integer_value != nullptr) return static_cast<double>(*value->integer_value);
  wrong_type(name, "a number");
}

bool Parameters::get_bool(const std::string& name, bool fallback) const {
  const rcl_variant_t* value = find(name);
  if (value == nullptr) return fallback;
  if (value->bool_value == nullptr) wrong_type(name, "true or false");
  return *value->bool_value;
}

std::vector<int64_t> Parameters::get_int_array(const std::string& name) const {
  const rcl_variant_t* value = find(name);
  if (value == nullptr) return {};
  if (value->integer_value != nullptr) return {*value->integer_value};
  if (value->integer_array_value == nullptr) wrong_type(name, "a list of integers");
  const rcl_int64_array_t& array = *value->integer_array_value;
  return std::vector<int64_t>(array.values, array.values + array.size);
}

std::vector<std::string> Parameters::get_string_array(const std::string& name) const {
  const rcl_variant_t* value = find(name);
  if (value == nullptr) return {};
  if (value->string_value != nullptr) return {value->string_value};
  if (value->string_array_value == nullptr) wrong_type(name, "a list of strings");
  const rcutils_string_array_t& array = *value->string_array_value;
  return std::vector<std::string>(array.data, array.data + array.size);
}

}  // namespace joshua
