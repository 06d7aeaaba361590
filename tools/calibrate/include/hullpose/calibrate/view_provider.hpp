#pragma once
// Where calibration images come from. A capture instant holds the images the cameras took at the
// same moment (one trigger); a board seen in two images of one instant links those cameras.
// Sources: a folder of images (below) or a live camera-node frame source (a thin adapter
// implementing ViewProvider over camera_node/source once that lands).
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hullpose::calibrate {

struct CameraImage {
  int camera_id = 0;
  cv::Mat image;  // 8-bit grey or BGR
};

struct CaptureInstant {
  std::string name;  // unique per instant; the floor view is found by name
  std::vector<CameraImage> images;
};

class ViewProvider {
 public:
  virtual ~ViewProvider() = default;
  // Fills `out` with the next instant; false once the source is exhausted (or stopped).
  virtual bool next(CaptureInstant& out) = 0;
  // For messages: "folder /data/calib", "camera node source ...".
  virtual std::string describe() const = 0;
};

// DIR/cam<ID>/<name>.png (or .jpg): images with the same <name> in several cam folders were taken
// at the same instant. Instants come in name order.
class FolderViewProvider final : public ViewProvider {
 public:
  // Throws hullpose::Error if DIR has no cam<ID> folder with images.
  explicit FolderViewProvider(std::filesystem::path dir);
  bool next(CaptureInstant& out) override;
  std::string describe() const override;
  const std::vector<int>& camera_ids() const { return camera_ids_; }
  size_t instant_count() const { return instants_.size(); }

 private:
  std::filesystem::path dir_;
  std::vector<int> camera_ids_;
  // name -> (camera id -> file)
  std::map<std::string, std::map<int, std::filesystem::path>> instants_;
  std::map<std::string, std::map<int, std::filesystem::path>>::const_iterator cursor_;
};

}  // namespace hullpose::calibrate
