// Reading structured device parameters: a device configures several similar things (encoder
// pairs, wheels, rangers, contacts) as named sub-blocks of one parameter. Errors are
// ParameterError lines naming the parameter, like every other parameter of the project.
#pragma once

#include "robot_core/parameters.h"
#include <ros/ros.h>

#include <string>
#include <vector>

namespace robot_core {
inline namespace parameter_reader {

// Names of the sub-blocks (dictionaries) under ~<name>; throws when missing, not a
// dictionary, empty, or when an entry is not a dictionary itself.
std::vector<std::string> requireBlockNames(const ros::NodeHandle& pnh, const std::string& name);

// Same, but an absent parameter yields an empty list.
std::vector<std::string> optionalBlockNames(const ros::NodeHandle& pnh, const std::string& name);

// A list of numbers under ~<name> (integers accepted); throws when present with another type.
std::vector<double> optionalDoubleList(const ros::NodeHandle& pnh, const std::string& name,
                                       const std::vector<double>& fallback);

// A name -> integer map under ~<name> (e.g. joystick axes), in key order.
std::vector<std::pair<std::string, int>> optionalIntMap(const ros::NodeHandle& pnh, const std::string& name);

// A list of strings under ~<name>.
std::vector<std::string> optionalStringList(const ros::NodeHandle& pnh, const std::string& name,
                                            const std::vector<std::string>& fallback);

}  // namespace parameter_reader
}  // namespace robot_core
