// hullpose-doctor: every start-up check of a hullpose board at once (tools/doctor/README.md).
// The units run it as ExecStartPre with --startup --role ROLE, so a failing check stops the
// service with its message and fix in the journal.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/doctor/checks.hpp"

namespace {
constexpr const char* kUsage =
    "usage: hullpose-doctor [--role all|camera-node|trigger-master|fusion-host|consumer]\n"
    "         [--config FILE] [--lcm-url URL] [--rig FILE] [--rig-key FILE]\n"
    "         [--trigger-line gpiod:CHIP:OFFSET] [--root DIR] [--startup] [--json]\n"
    "  Checks what silently breaks LCM and the trigger on this host: receive buffers, the\n"
    "  multicast route and TTL, the clock's synchronisation, the trigger GPIO, the camera, the\n"
    "  rig file and the rig key; each failure says what to run. Without options: everything\n"
    "  /etc/hullpose/ configures.\n"
    "  --config FILE   a camera node's config (instead of every /etc/hullpose/camera*.yaml)\n"
    "  --root DIR      read procfs, sysfs, /dev and /etc under DIR (a fake tree; tests)\n"
    "  --startup       print only what is not ok (for ExecStartPre)\n"
    "  Exit status: 0 nothing failed (warnings allowed), 1 a check failed, 2 bad options.\n";

int run(int argc, const char* const* argv) {
  using namespace hullpose;
  std::string role_text = "all", config, lcm_url, rig, rig_key, trigger_line, root = "/";
  bool startup = false, json = false, lcm_given = false, key_given = false;
  cli::CommandLine line(kUsage);
  line.option("--role", role_text)
      .option("--config", config)
      .option("--lcm-url", [&](const std::string& v) { lcm_url = v, lcm_given = true; })
      .option("--rig", rig)
      .option("--rig-key", [&](const std::string& v) { rig_key = v, key_given = true; })
      .option("--trigger-line", trigger_line)
      .option("--root", root)
      .flag("--startup", startup)
      .flag("--json", json);
  if (!line.parse(argc, argv)) return 0;
  const doctor::Role role = doctor::parse_role(role_text);
  const doctor::Host host(root);
  doctor::Setup setup =
      doctor::setup_from_etc(host, config.empty() ? role : doctor::Role::kFusionHost);
  setup.role = role;
  if (!config.empty()) setup.cameras = {doctor::load_camera(host, config)};
  if (lcm_given) setup.lcm_url = lcm_url;
  if (!rig.empty()) setup.rig_file = rig;
  if (key_given) setup.rig_key = rig_key;  // "" (an open rig) too
  if (!trigger_line.empty()) setup.trigger_line = trigger_line;

  const std::vector<doctor::Result> results = doctor::run_checks(host, setup);
  bool failed = false;
  nlohmann::json out = nlohmann::json::array();
  for (const doctor::Result& r : results) {
    failed = failed || r.status == doctor::Status::kFail;
    if (json) {
      out.push_back({{"check", r.check},
                     {"status", doctor::status_name(r.status)},
                     {"message", r.message},
                     {"fix", r.fix}});
      continue;
    }
    if (startup && (r.status == doctor::Status::kOk || r.status == doctor::Status::kSkip)) continue;
    std::printf("[%-4s] %s: %s\n", doctor::status_name(r.status), r.check.c_str(),
                r.message.c_str());
    if (!r.fix.empty()) std::printf("       fix: %s\n", r.fix.c_str());
  }
  if (json) std::cout << out.dump(2) << "\n";
  std::fflush(stdout);
  return failed ? 1 : 0;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-doctor", argc, argv, run);
}
