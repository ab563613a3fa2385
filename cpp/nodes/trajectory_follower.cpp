// The action-chunk rule of trajectory_follower.hpp.
#include "nodes/trajectory_follower.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace joshua {
namespace {

constexpr double NANOSECONDS_PER_SECOND = 1e9;

template <class Time>
double seconds(const Time& time) {
  return time.sec + time.nanosec / NANOSECONDS_PER_SECOND;
}

std::string fixed3(const char* before, double value, const char* after) {
  char text[96];
  std::snprintf(text, sizeof text, "%s%.3f%s", before, value, after);
  return text;
}

// Positions at `at_s`, linear between points, the first before them and the last after them.
std::vector<double> sample(const std::vector<double>& times, const std::vector<std::vector<double>>& positions,
                           double at_s) {
  if (at_s <= times.front()) return positions.front();
  if (at_s >= times.back()) return positions.back();
  const size_t after = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), at_s) - times.begin());
  const double weight = (at_s - times[after - 1]) / (times[after] - times[after - 1]);
  std::vector<double> goal(positions[after].size());
  for (size_t j = 0; j < goal.size(); ++j) {
    goal[j] = positions[after - 1][j] + weight * (positions[after][j] - positions[after - 1][j]);
  }
  return goal;
}

}  // namespace

double ros_now_s() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  return std::chrono::duration_cast<std::chrono::nanoseconds>(now).count() / NANOSECONDS_PER_SECOND;
}

bool chunk_from_trajectory(const trajectory_msgs::msg::JointTrajectory& message,
                           const std::vector<std::string>& joint_names, double arrival_s, Chunk& chunk,
                           std::string& why) {
  const size_t width = joint_names.size();
  std::vector<std::pair<size_t, size_t>> columns;  // (column in the message, joint index)
  size_t named = message.joint_names.size();
  if (named) {
    std::map<std::string, size_t> index;
    for (size_t j = 0; j < width; ++j) index.emplace(joint_names[j], j);
    for (size_t column = 0; column < named; ++column) {
      auto found = index.find(message.joint_names[column]);
      if (found != index.end()) columns.emplace_back(column, found->second);
    }
  } else if (!message.points.empty() && message.points.front().positions.size() == width) {
    named = width;
    for (size_t j = 0; j < width; ++j) columns.emplace_back(j, j);
  } else {
    why = "the trajectory names no joints and its points do not have " + std::to_string(width) + " positions";
    return false;
  }
  if (message.points.empty()) {
    why = "the trajectory has no points";
    return false;
  }
  const double stamp = seconds(message.header.stamp);
  chunk.stamp_s = stamp != 0 ? stamp : arrival_s;
  chunk.times_s.clear();
  chunk.positions.clear();
  for (size_t row = 0; row < message.points.size(); ++row) {
    const auto& point = message.points[row];
    if (point.positions.size() != named) {
      why = "point " + std::to_string(row) + " has " + std::to_string(point.positions.size()) + " positions for " +
            std::to_string(named) + " joints";
      return false;
    }
    std::vector<double> goals(width, std::numeric_limits<double>::quiet_NaN());
    for (const auto& [column, joint] : columns) goals[joint] = point.positions[column];
    const double at = chunk.stamp_s + seconds(point.time_from_start);
    if (!chunk.times_s.empty() && at <= chunk.times_s.back()) {
      why = "time_from_start does not increase from point to point";
      return false;
    }
    chunk.times_s.push_back(at);
    chunk.positions.push_back(std::move(goals));
  }
  return true;
}

std::string TrajectoryFollower::accept(const Chunk& chunk, double now_s) {
  if (chunk.stamp_s < stamp_s_) return fixed3("stamped ", stamp_s_ - chunk.stamp_s, " s before the chunk in force");
  if (chunk.times_s.back() <= now_s) {
    return fixed3("its last point was ", now_s - chunk.times_s.back(), " s in the past on arrival");
  }
  const std::vector<double> own = sample(chunk.times_s, chunk.positions, now_s);
  std::vector<double> start = goal(now_s);
  if (start.empty()) {
    start = own;
  } else {
    for (size_t j = 0; j < start.size(); ++j) {
      if (std::isnan(start[j])) start[j] = own[j];
    }
  }
  times_ = {now_s};
  positions_ = {start};
  for (size_t row = 0; row < chunk.times_s.size(); ++row) {
    if (chunk.times_s[row] > now_s) {
      times_.push_back(chunk.times_s[row]);
      positions_.push_back(chunk.positions[row]);
    }
  }
  stamp_s_ = chunk.stamp_s;
  return "";
}

std::vector<double> TrajectoryFollower::goal(double now_s) const {
  if (times_.empty()) return {};
  return sample(times_, positions_, now_s);
}

}  // namespace joshua
