// hullpose-rig-key: makes a rig's key file (docs/messages.md, "Authentication"): 32 random
// bytes as 64 hex digits, mode 0600, never overwriting a file. Copy it to every host of the rig
// (scp keeps it private) and name it with --rig-key / rig_key: in each process's options.
#include <cstdio>
#include <optional>
#include <string>

#include "hullpose/auth/rig_key.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"

namespace {
const char* kUsage =
    "usage: hullpose-rig-key --output FILE     writes a new random rig key (mode 0600)\n"
    "       hullpose-rig-key --check FILE      checks a key file, prints its key id\n";
}

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-rig-key", argc, argv, [](int c, const char* const* v) {
    std::string output, check;
    hullpose::cli::CommandLine cl(kUsage);
    cl.option("--output", output).option("--check", check);
    if (!cl.parse(c, v)) return 0;
    HULLPOSE_THROW_UNLESS(output.empty() != check.empty(),
                          "give one of --output FILE or --check FILE (see --help)");
    if (!output.empty()) {
      const auto key = hullpose::auth::RigKey::generate();
      key.save(output);
      std::printf("hullpose-rig-key: wrote %s (key id %08x)\n", output.c_str(), key.id());
    } else {
      std::printf("hullpose-rig-key: %s is a valid rig key (key id %08x)\n", check.c_str(),
                  hullpose::auth::RigKey::load(check).id());
    }
    return 0;
  });
}
