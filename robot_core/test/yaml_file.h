// A YAML text written to a fresh file under /tmp for a reader test; the caller removes it.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

inline std::string writeYaml(const std::string& text) {
  char name[] = "/tmp/test_yaml_XXXXXX";
  const int fd = mkstemp(name);
  close(fd);
  std::ofstream(name) << text;
  return name;
}
