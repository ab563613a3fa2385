// Named poses of an arm (home, rest, grip_open and a description's own) and their goals (as joshua_runtime.presets).
//
// A preset command is a name sent on `<topic_name>/preset`: torque_on and torque_off switch torque; a pose
// name becomes goal positions (NaN for the joints the pose leaves alone).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace joshua {

extern const char* const TORQUE_ON;
extern const char* const TORQUE_OFF;

struct Pose {
  std::string name;
  std::map<std::string, double> positions;  // rad by joint name
};

class Presets {
 public:
  // The built-in poses with the description's own added; `own_json` is the `preset` parameter,
  // {"name": {"joint": rad, ...}, ...} ("" for none). SettingsError for a joint not in `joints`.
  Presets(const std::string& own_json, std::vector<std::string> joints);

  // Goals in joint order for a pose name (NaN: leave alone); false for a name that is no pose.
  bool goals(const std::string& name, std::vector<double>& goals) const;
  // "torque_on, torque_off, home, rest, grip_open, ..." for an unknown-preset message.
  std::string known() const;

 private:
  void add(Pose pose);

  std::vector<std::string> joints_;
  std::vector<Pose> poses_;  // built-ins first, in their order
};

// The way Python's repr() quotes a string: 'text' (or "text" when it holds ' but no ").
std::string python_repr(const std::string& text);

}  // namespace joshua
