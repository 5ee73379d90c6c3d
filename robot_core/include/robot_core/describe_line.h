// One line of a reader's --describe (check_components, check_sim_config): what it declared of one
// parameter, tab-separated, as robot_tools.docs.parameter_tables reads it and as the Python twin
// robot_core.params.declaration_lines writes it:
//   component<tab>name<tab>type<tab>required|optional<tab>default<tab>rule<tab>meaning
#pragma once

#include <string>

#include "robot_core/params.h"

namespace robot_core {

inline std::string describeLine(const std::string& component, const std::string& name, const ParameterDeclaration& d) {
  return component + "\t" + name + "\t" + d.type + "\t" + (d.required ? "required" : "optional") + "\t" + d.fallback +
         "\t" + d.rule + "\t" + d.meaning;
}

}  // namespace robot_core
