#include "hullpose/camera_node/file_source.hpp"
#include "hullpose/camera_node/frame_source.hpp"
#include "hullpose/camera_node/v4l2_source.hpp"
#include "hullpose/common/check.hpp"
#if HULLPOSE_HAVE_LIBCAMERA
#include "hullpose/camera_node/libcamera_source.hpp"
#endif
#if HULLPOSE_HAVE_SYNTHETIC_SOURCE
#include "hullpose/camera_node/synthetic_source.hpp"
#endif

namespace hullpose::camera_node {

SourceRegistry& SourceRegistry::builtin() {
  static SourceRegistry registry = [] {
    SourceRegistry r;
#if HULLPOSE_HAVE_LIBCAMERA
    r.add("libcamera", [](const Params& p, const SourceContext& c) {
      return std::make_unique<LibcameraSource>(p, c);
    });
#else
    r.add_unavailable("libcamera",
                      "this build has no libcamera (install libcamera-dev and configure with "
                      "-DHULLPOSE_LIBCAMERA=ON)");
#endif
    r.add("v4l2", [](const Params& p, const SourceContext& c) {
      return std::make_unique<V4l2Source>(p, c);
    });
    r.add("file", [](const Params& p, const SourceContext& c) {
      return std::make_unique<FileSource>(p, c);
    });
#if HULLPOSE_HAVE_SYNTHETIC_SOURCE
    r.add("synthetic", [](const Params& p, const SourceContext& c) {
      return std::make_unique<SyntheticSource>(p, c);
    });
#else
    r.add_unavailable(
        "synthetic",
        "this build has no synthetic source (configure with -DHULLPOSE_SYNTHETIC_SOURCE=ON)");
#endif
    return r;
  }();
  return registry;
}

void SourceRegistry::add(std::string name, SourceFactory factory) {
  for (auto& [n, f] : factories_) {
    if (n == name) {
      f = std::move(factory);
      return;
    }
  }
  factories_.emplace_back(std::move(name), std::move(factory));
}

void SourceRegistry::add_unavailable(std::string name, std::string why) {
  add(name, [name, why](const Params& p, const SourceContext&) -> std::unique_ptr<FrameSource> {
    HULLPOSE_THROW(p.scope() << ".type: source '" << name << "': " << why);
  });
}

std::vector<std::string> SourceRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& entry : factories_) out.push_back(entry.first);
  return out;
}

std::unique_ptr<FrameSource> SourceRegistry::create(const std::string& name, const Params& params,
                                                    const SourceContext& context) const {
  for (const auto& [n, factory] : factories_) {
    if (n != name) continue;
    std::unique_ptr<FrameSource> source = factory(params, context);
    params.expect_all_used();
    return source;
  }
  std::string known;
  for (const auto& entry : factories_) known += (known.empty() ? "" : ", ") + entry.first;
  HULLPOSE_THROW(params.scope() << ".type: unknown source '" << name << "' (known: " << known
                                << ")");
}

}  // namespace hullpose::camera_node
