#pragma once

#include <stdexcept>

namespace robot_core {

// Thrown for bad configuration. what() is the one line the user sees.
class ParameterError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace robot_core
