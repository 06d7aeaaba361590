#pragma once
// The production camera: libcamera (0.0.x API) with fixed exposure, gain and frame duration,
// and the sensor's external-trigger mode where it has one. Parameters:
//   camera            libcamera id or index in the camera list (default: the first camera)
//   exposure_us       fixed exposure (4000); analogue_gain (1.0); auto exposure is off
//   frame_duration_us fixed frame duration (33333); ignored by the sensor in trigger mode
//   external_trigger  false | true: the sensor exposes on the trigger line's edge. libcamera
//                     0.0.x has no control for it; sensors that support it expose a module
//                     parameter (/sys/module/<driver>/parameters/trigger_mode, e.g. imx296 on the
//                     Raspberry Pi global-shutter camera), which is set before streaming; a sensor
//                     without one is an error that names the sensor and the path tried.
//   buffers           requests in flight (4)
// Timestamps: the SensorTimestamp of each completed request (start of exposure, CLOCK_BOOTTIME
// nanoseconds), mapped to the epoch.
#include <memory>

#include "hullpose/camera_node/frame_source.hpp"

namespace hullpose::camera_node {

class LibcameraSource final : public FrameSource {
 public:
  LibcameraSource(const Params& params, const SourceContext& context);
  ~LibcameraSource() override;
  void start() override;
  GrabStatus grab(Frame& frame, int timeout_ms) override;
  void stop() override;
  std::string describe() const override;

  struct Impl;  // the libcamera objects; keeps libcamera's headers out of this one

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace hullpose::camera_node
