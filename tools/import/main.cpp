// hullpose-import: rigs and datasets from other tools' calibrations and silhouettes.
#include <iostream>

#include "hullpose/common/tool.hpp"
#include "hullpose/import/cli.hpp"

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-import", argc, argv, [](int c, const char* const* v) {
    return hullpose::import::run_cli(c, v, std::cout);
  });
}
