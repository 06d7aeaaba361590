// Writes the small rig of rig_fixtures.hpp as a rig file: write_test_rig OUT.yaml N W H [RIG_ID]
#include <cstdio>
#include <string>

#include "hullpose/common/check.hpp"
#include "rig_fixtures.hpp"

int main(int argc, char** argv) {
  try {
    HULLPOSE_THROW_UNLESS(argc >= 5, "usage: write_test_rig OUT.yaml N W H [RIG_ID]");
    hullpose::save_rig(hullpose::testing::make_rig(std::stoi(argv[2]), std::stoi(argv[3]), std::stoi(argv[4]),
                                                   argc > 5 ? argv[5] : "rigA"),
                       argv[1]);
    return 0;
  } catch (const hullpose::Error& e) {
    std::fprintf(stderr, "write_test_rig: error: %s\n", e.what());
    return 2;
  }
}
