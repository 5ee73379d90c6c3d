#include "robot_core/configurable_component.h"

namespace robot_core {

// Defined here, once, so every package sees one type (the checker's dynamic_cast across plugins).
ConfigurableComponent::~ConfigurableComponent() = default;

}  // namespace robot_core
