// A number of a config struct as a reader's table row: its parameter name, where the value goes,
// what it means (robot_core::Params::describe, the generated parameter tables). Readers that read
// several numbers by one rule loop over a table of these.
#pragma once

namespace hal_nodes {

struct DescribedNumber {
  const char* name;
  double* value;
  const char* meaning;
};

}  // namespace hal_nodes
