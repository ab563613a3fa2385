// Translation of the QoS policy names joshuac writes (RELIABLE, TRANSIENT_LOCAL, ...) into rmw values.
#include "joshua_rcl/qos.hpp"

#include <map>
#include <string>

#include "joshua_rcl/errors.hpp"
#include "rmw/qos_profiles.h"

namespace joshua {
namespace {

const int64_t DEFAULT_DEPTH = 10;

template <class Policy>
Policy lookup(const std::map<std::string, Policy>& names, const Parameters& parameters, const std::string& key,
              const std::string& fallback) {
  const std::string value = parameters.get_string(key, fallback);
  auto found = names.find(value);
  if (found == names.end()) throw SettingsError("parameter " + key + " has unknown value " + value);
  return found->second;
}

}  // namespace

rmw_qos_profile_t qos_from_parameters(const Parameters& parameters) {
  static const std::map<std::string, rmw_qos_reliability_policy_e> reliability = {
      {"RELIABLE", RMW_QOS_POLICY_RELIABILITY_RELIABLE}, {"BEST_EFFORT", RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT}};
  static const std::map<std::string, rmw_qos_durability_policy_e> durability = {
      {"VOLATILE", RMW_QOS_POLICY_DURABILITY_VOLATILE},
      {"TRANSIENT_LOCAL", RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL}};
  static const std::map<std::string, rmw_qos_history_policy_e> history = {
      {"KEEP_LAST", RMW_QOS_POLICY_HISTORY_KEEP_LAST}, {"KEEP_ALL", RMW_QOS_POLICY_HISTORY_KEEP_ALL}};

  rmw_qos_profile_t qos = rmw_qos_profile_default;
  qos.reliability = lookup(reliability, parameters, "qos_reliability", "RELIABLE");
  qos.durability = lookup(durability, parameters, "qos_durability", "VOLATILE");
  qos.history = lookup(history, parameters, "qos_history", "KEEP_LAST");
  const int64_t depth = parameters.get_int("qos_depth", DEFAULT_DEPTH);
  if (depth < 0) throw SettingsError("parameter qos_depth must not be negative");
  qos.depth = qos.history == RMW_QOS_POLICY_HISTORY_KEEP_ALL ? 0 : static_cast<size_t>(depth);
  return qos;
}

rmw_qos_profile_t fixed_qos() {
  rmw_qos_profile_t qos = rmw_qos_profile_default;
  qos.reliability = RMW_QOS_POLICY_RELIABILITY_RELIABLE;
  qos.durability = RMW_QOS_POLICY_DURABILITY_VOLATILE;
  qos.history = RMW_QOS_POLICY_HISTORY_KEEP_LAST;
  qos.depth = DEFAULT_DEPTH;
  return qos;
}

}  // namespace joshua
