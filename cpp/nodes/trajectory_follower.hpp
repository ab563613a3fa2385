// Following action chunks (trajectory_msgs/msg/JointTrajectory) at the actuator's own control rate, by the
// rule of joshua_runtime.nodes.trajectory_follower (same behaviour; tests/cpp checks they agree):
// points at header.stamp + time_from_start (a zero stamp: on arrival); a newer chunk replaces the rest of
// the one in force, its past points dropped, the goal moving linearly from the goal in force (for the
// first chunk, the chunk's own value then) to each point ahead; the last point held once it has passed;
// chunks entirely in the past or stamped before the one in force change nothing.
#pragma once

#include <string>
#include <vector>

#include "trajectory_msgs/msg/joint_trajectory.hpp"

namespace joshua {

// Timed goals in the follower's joint order: times on the ROS clock (s), positions[point][joint] (NaN: absent).
struct Chunk {
  double stamp_s = 0;
  std::vector<double> times_s;
  std::vector<std::vector<double>> positions;
};

// Now on the ROS clock (the wall clock when no simulated time is used), in seconds.
double ros_now_s();

// The Chunk of a JointTrajectory in `joint_names` order; false with `why` set when it cannot be followed.
bool chunk_from_trajectory(const trajectory_msgs::msg::JointTrajectory& message,
                           const std::vector<std::string>& joint_names, double arrival_s, Chunk& chunk,
                           std::string& why);

class TrajectoryFollower {
 public:
  // Takes a chunk received at `now_s`; "" when it is followed, else why it was dropped.
  std::string accept(const Chunk& chunk, double now_s);
  // The goal at `now_s` (NaN: leave the joint alone); empty before the first chunk.
  std::vector<double> goal(double now_s) const;
  // Whether a chunk is in force at `now_s` (received and its last point not yet passed).
  bool executing(double now_s) const { return !times_.empty() && now_s <= times_.back(); }

 private:
  std::vector<double> times_;
  std::vector<std::vector<double>> positions_;
  double stamp_s_ = -1e300;
};

}  // namespace joshua
