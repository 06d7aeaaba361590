// hullpose-import: rigs and datasets from other tools' calibrations and silhouettes.
#include <iostream>

#include "hullpose/import/cli.hpp"

int main(int argc, char** argv) {
  return hullpose::import::run_cli(argc, argv, std::cout, std::cerr);
}
