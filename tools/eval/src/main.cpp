// hullpose-eval: scores a pose estimate file against a dataset's ground truth.
#include <iostream>

#include "hullpose/eval/cli.hpp"

int main(int argc, char** argv) {
  return hullpose::eval::run_cli(argc, argv, std::cout, std::cerr);
}
