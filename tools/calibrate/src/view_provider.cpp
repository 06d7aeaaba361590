#include "hullpose/calibrate/view_provider.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <opencv2/imgcodecs.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate {
namespace fs = std::filesystem;

namespace {

// "cam12" -> 12; anything else -> -1.
int camera_id_of(const std::string& folder) {
  if (folder.size() < 4 || folder.compare(0, 3, "cam") != 0) return -1;
  int id = -1;
  const char* first = folder.data() + 3;
  const char* last = folder.data() + folder.size();
  const auto [ptr, ec] = std::from_chars(first, last, id);
  if (ec != std::errc() || ptr != last || id < 0) return -1;
  return id;
}

bool is_image(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".pgm";
}

}  // namespace

FolderViewProvider::FolderViewProvider(fs::path dir) : dir_(std::move(dir)) {
  HULLPOSE_THROW_UNLESS(fs::is_directory(dir_), dir_.string() << ": not a directory");
  for (const auto& entry : fs::directory_iterator(dir_)) {
    if (!entry.is_directory()) continue;
    const int id = camera_id_of(entry.path().filename().string());
    if (id < 0) continue;
    bool any = false;
    for (const auto& file : fs::directory_iterator(entry.path())) {
      if (!file.is_regular_file() || !is_image(file.path())) continue;
      instants_[file.path().stem().string()][id] = file.path();
      any = true;
    }
    if (any) camera_ids_.push_back(id);
  }
  std::sort(camera_ids_.begin(), camera_ids_.end());
  HULLPOSE_THROW_UNLESS(!camera_ids_.empty(),
                        dir_.string() << ": no cam<ID>/ folder with images (.png, .jpg) found");
  cursor_ = instants_.begin();
}

bool FolderViewProvider::next(CaptureInstant& out) {
  if (cursor_ == instants_.end()) return false;
  out.name = cursor_->first;
  out.images.clear();
  for (const auto& [id, path] : cursor_->second) {
    cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    HULLPOSE_THROW_UNLESS(!image.empty(), path.string() << ": cannot read image");
    out.images.push_back({id, std::move(image)});
  }
  ++cursor_;
  return true;
}

std::string FolderViewProvider::describe() const {
  return "folder " + dir_.string();
}

}  // namespace hullpose::calibrate
