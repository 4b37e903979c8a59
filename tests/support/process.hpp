// Running the geobrush program from tests.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace geobrush::test {

struct ProcessResult {
  int status = -1;  // exit status
  std::string out;
  std::string err;
  // Lines of stderr that start with "error:".
  int errorLines() const;
};

// Runs the CLI with `args` (each passed as one argument) and extra
// environment variables; captures stdout and stderr.
ProcessResult runCli(const std::vector<std::string>& args,
                     const std::map<std::string, std::string>& env = {});

}  // namespace geobrush::test
