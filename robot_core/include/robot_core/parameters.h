// Reading ~parameters strictly: a missing or out-of-range value stops the node at start
// with one line naming the parameter and what is allowed, never a silent default.
// A whole block read by a config reader shared with benches and tests: params.h.
#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "robot_core/parameter_error.h"

namespace robot_core {
// The reader's names live in an inline namespace so a source file can take exactly them with one
// `using namespace robot_core::parameter_reader;` (in a .cpp only: a header would impose it on its includers).
inline namespace parameter_reader {

// Required parameters: throw ParameterError when missing or of the wrong type.
double requireDouble(const ros::NodeHandle& pnh, const std::string& name);
int requireInt(const ros::NodeHandle& pnh, const std::string& name);
std::string requireString(const ros::NodeHandle& pnh, const std::string& name);

// Optional parameters with a documented default; a present value of the wrong type still throws.
double optionalDouble(const ros::NodeHandle& pnh, const std::string& name, double fallback);
int optionalInt(const ros::NodeHandle& pnh, const std::string& name, int fallback);
bool optionalBool(const ros::NodeHandle& pnh, const std::string& name, bool fallback);
std::string optionalString(const ros::NodeHandle& pnh, const std::string& name, const std::string& fallback);

// Range checks: throw ParameterError("<ns>/<name> = <v>: must be ...").
void requirePositive(const ros::NodeHandle& pnh, const std::string& name, double value);
void requireInRange(const ros::NodeHandle& pnh, const std::string& name, double value, double lo, double hi);
void requireOneOf(const ros::NodeHandle& pnh, const std::string& name, const std::string& value,
                  const std::vector<std::string>& allowed);

// A parameter that was renamed: the name to read. The old name still works while the new one is
// absent, with a warning naming both, so a team's config keeps starting after an update.
std::string renamed(const ros::NodeHandle& pnh, const std::string& now, const std::string& old);

// The fully resolved parameter name, for messages.
std::string qualified(const ros::NodeHandle& pnh, const std::string& name);

}  // namespace parameter_reader
}  // namespace robot_core
