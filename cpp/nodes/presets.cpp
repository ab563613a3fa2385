// The built-in poses and the description's own, read from the `preset` parameter (JSON).
#include "nodes/presets.hpp"

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>

#include "joshua_rcl/errors.hpp"

namespace joshua {

const char* const TORQUE_ON = "torque_on";
const char* const TORQUE_OFF = "torque_off";

namespace {

// Joint poses in rad of the SO-100 arm; a joint left out keeps its goal.
const std::vector<Pose>& builtin_poses() {
  static const std::vector<Pose> poses = {
      {"home", {{"shoulder_pan", 0.0}, {"shoulder_lift", 0.0}, {"elbow_flex", 0.0}, {"wrist_flex", 0.0},
                {"wrist_roll", 0.0}, {"gripper", 0.0}}},
      {"rest", {{"shoulder_pan", 0.0}, {"shoulder_lift", -1.65}, {"elbow_flex", 1.55}, {"wrist_flex", 0.7},
                {"wrist_roll", 0.0}, {"gripper", 0.0}}},
      {"grip_open", {{"gripper", 1.5}}},
  };
  return poses;
}

std::string listed(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace

Presets::Presets(const std::string& own_json, std::vector<std::string> joints) : joints_(std::move(joints)) {
  for (const Pose& pose : builtin_poses()) add(pose);
  if (own_json.empty()) return;
  nlohmann::ordered_json own;
  try {
    own = nlohmann::ordered_json::parse(own_json);
  } catch (const nlohmann::json::exception& error) {
    throw SettingsError(std::string("parameter preset is not JSON: ") + error.what());
  }
  if (!own.is_object()) throw SettingsError("parameter preset must be a JSON object of poses by name");
  for (const auto& [name, positions] : own.items()) {
    if (!positions.is_object()) throw SettingsError("preset " + python_repr(name) + " must map joint names to radians");
    Pose pose{name, {}};
    std::vector<std::string> unknown;
    for (const auto& [joint, value] : positions.items()) {
      if (!value.is_number()) throw SettingsError("preset " + python_repr(name) + ": " + joint + " is not a number");
      if (std::find(joints_.begin(), joints_.end(), joint) == joints_.end()) unknown.push_back(joint);
      pose.positions[joint] = value.get<double>();
    }
    if (!unknown.empty()) {
      std::sort(unknown.begin(), unknown.end());
      throw SettingsError("preset " + python_repr(name) + " names joint " + python_repr(unknown.front()) + ", not one of " +
                          listed(joints_));
    }
    add(std::move(pose));
  }
}

void Presets::add(Pose pose) {
  auto same = std::find_if(poses_.begin(), poses_.end(), [&](const Pose& known) { return known.name == pose.name; });
  if (same == poses_.end()) {
    poses_.push_back(std::move(pose));
  } else {
    *same = std::move(pose);  // the description's own replaces a built-in of the same name
  }
}

bool Presets::goals(const std::string& name, std::vector<double>& goals) const {
  auto pose = std::find_if(poses_.begin(), poses_.end(), [&](const Pose& known) { return known.name == name; });
  if (pose == poses_.end()) return false;
  goals.assign(joints_.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < joints_.size(); ++i) {
    auto position = pose->positions.find(joints_[i]);
    if (position != pose->positions.end()) goals[i] = position->second;
  }
  return true;
}

std::string Presets::known() const {
  std::vector<std::string> names = {TORQUE_ON, TORQUE_OFF};
  for (const Pose& pose : poses_) names.push_back(pose.name);
  return listed(names);
}

std::string python_repr(const std::string& text) {
  const bool double_quotes = text.find('\'') != std::string::npos && text.find('"') == std::string::npos;
  const char quote = double_quotes ? '"' : '\'';
  std::string result(1, quote);
  for (char c : text) {
    if (c == quote || c == '\\') result += '\\';
    result += c;
  }
  return result + quote;
}

}  // namespace joshua
