// hullpose-export: a recorded take (estimate CSV or lcm-logger log) to BVH, TRC and/or C3D.
// Gap policy: tools/skeleton_io/include/hullpose/skeleton_io/gaps.hpp; formats: README.md.
#include <cstdio>
#include <fstream>
#include <optional>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/skeleton_io/export.hpp"

namespace {
const char* kUsage =
    "usage: hullpose-export --in TAKE (estimate .csv | lcm-logger log) [--bvh FILE] [--trc FILE] "
    "[--c3d FILE]\n"
    "         [--fps F (CSV only, default 30)] [--channel SKELETON] [--max-gap-ms 200] [--gaps "
    "FILE.json]\n";
}  // namespace

int run(int argc, const char* const* argv) {
  hullpose::skeleton_io::ExportOptions o;
  hullpose::cli::CommandLine cl(kUsage);
  cl.option("--in", o.input)
      .option("--bvh", o.bvh)
      .option("--trc", o.trc)
      .option("--c3d", o.c3d)
      .option("--fps", o.fps)
      .option("--channel", o.channel)
      .option("--max-gap-ms", o.max_gap_ms)
      .option("--gaps", o.gaps_json);
  if (!cl.parse(argc, argv)) return 0;
  std::fprintf(stderr, "hullpose-export: %s\n", hullpose::skeleton_io::export_take(o).c_str());
  return 0;
}

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-export", argc, argv, run);
}
