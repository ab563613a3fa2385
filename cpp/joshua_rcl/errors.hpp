// Failures a node reports as one line on stderr, with the exit codes of core/joshua_core/exit_codes.py.
#pragma once

#include <stdexcept>
#include <string>

namespace joshua {

// A failure meant for the robot operator: exit code 1.
class JoshuaError : public std::runtime_error {
 public:
  explicit JoshuaError(const std::string& message, int exit_code = 1)
      : std::runtime_error(message), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

// A device is missing, cannot be opened, or stopped answering: exit code 3.
class DeviceError : public JoshuaError {
 public:
  explicit DeviceError(const std::string& message) : JoshuaError(message, 3) {}
};

// The settings handed to a node are unusable: exit code 2.
class SettingsError : public JoshuaError {
 public:
  explicit SettingsError(const std::string& message) : JoshuaError(message, 2) {}
};

// SIGINT or SIGTERM arrived while the node was still starting: a clean exit (code 0).
class StopRequested : public std::exception {
 public:
  const char* what() const noexcept override { return "stop requested"; }
};

}  // namespace joshua
