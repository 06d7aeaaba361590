// hullpose-eval: scores a pose estimate file against a dataset's ground truth.
#include <iostream>

#include "hullpose/common/tool.hpp"
#include "hullpose/eval/cli.hpp"

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-eval", argc, argv, [](int c, const char* const* v) {
    return hullpose::eval::run_cli(c, v, std::cout);
  });
}
