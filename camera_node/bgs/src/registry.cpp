#include <functional>

#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/codebook.hpp"
#include "hullpose/camera_node/horprasert.hpp"
#include "hullpose/camera_node/opencv_subtractors.hpp"
#include "hullpose/camera_node/sobs.hpp"
#include "hullpose/camera_node/threshold.hpp"
#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {
namespace {

struct Entry {
  const char* name;
  std::unique_ptr<BackgroundSubtractor> (*make)(const Params&);
};

const Entry kMethods[] = {
    {"horprasert",
     [](const Params& p) -> std::unique_ptr<BackgroundSubtractor> {
       return std::make_unique<Horprasert>(HorprasertParams::from(p));
     }},
    {"codebook",
     [](const Params& p) -> std::unique_ptr<BackgroundSubtractor> {
       return std::make_unique<Codebook>(CodebookParams::from(p));
     }},
    {"sobs",
     [](const Params& p) -> std::unique_ptr<BackgroundSubtractor> {
       return std::make_unique<Sobs>(SobsParams::from(p));
     }},
    {"mog2",
     [](const Params& p) -> std::unique_ptr<BackgroundSubtractor> {
       return std::make_unique<OpenCvSubtractor>(OpenCvSubtractor::Kind::kMog2, p);
     }},
    {"knn",
     [](const Params& p) -> std::unique_ptr<BackgroundSubtractor> {
       return std::make_unique<OpenCvSubtractor>(OpenCvSubtractor::Kind::kKnn, p);
     }},
    {"threshold",
     [](const Params& p) -> std::unique_ptr<BackgroundSubtractor> {
       return std::make_unique<ThresholdSubtractor>(p);
     }},
};

}  // namespace

std::vector<std::string> subtractor_names() {
  std::vector<std::string> names;
  for (const Entry& e : kMethods) names.emplace_back(e.name);
  return names;
}

std::unique_ptr<BackgroundSubtractor> make_subtractor(const std::string& method,
                                                      const Params& params) {
  for (const Entry& e : kMethods)
    if (method == e.name) return e.make(params);
  std::string known;
  for (const Entry& e : kMethods) known += (known.empty() ? "" : ", ") + std::string(e.name);
  HULLPOSE_THROW("bgs.method: unknown method '" << method << "' (known: " << known << ")");
}

}  // namespace hullpose::camera_node
