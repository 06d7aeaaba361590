// CudaFusion: device buffers, uploads and the CK3 iteration loop on the host side; the kernels
// are in cuda_kernels.cu.
#include "hullpose/gpu/cuda_fusion.hpp"

#include <cuda_runtime_api.h>

#include <bit>
#include <opencv2/imgproc.hpp>

#include "cuda_kernels.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/gpu/backend.hpp"
#include "hullpose/thin/simple_lut.hpp"

namespace hullpose::gpu {

namespace {

void check(cudaError_t e, const char* what) {
  HULLPOSE_THROW_UNLESS(e == cudaSuccess,
                        "CUDA backend: " << what << ": " << cudaGetErrorString(e));
}
void check_launch(int e, const char* what) {
  check(static_cast<cudaError_t>(e), what);
}

// One device allocation, freed with its owner.
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept : p_(o.p_), bytes_(o.bytes_) { o.p_ = nullptr; }
  ~DeviceBuffer() {
    if (p_) cudaFree(p_);
  }
  void allocate(size_t bytes, const char* what) {
    check(cudaMalloc(&p_, bytes), what);
    bytes_ = bytes;
  }
  template <class T>
  T* as() const {
    return static_cast<T*>(p_);
  }
  size_t bytes() const { return bytes_; }

 private:
  void* p_ = nullptr;
  size_t bytes_ = 0;
};

class Event {
 public:
  Event() { check(cudaEventCreate(&e_), "cudaEventCreate"); }
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;
  ~Event() { cudaEventDestroy(e_); }
  void record() { check(cudaEventRecord(e_, nullptr), "cudaEventRecord"); }
  double ms_since(const Event& start) const {
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start.e_, e_), "cudaEventElapsedTime");
    return static_cast<double>(ms);
  }
  void wait() { check(cudaEventSynchronize(e_), "cudaEventSynchronize"); }

 private:
  cudaEvent_t e_{};
};

void upload(void* dst, const void* src, size_t bytes, const char* what) {
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice), what);
}
void download(void* dst, const void* src, size_t bytes, const char* what) {
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost), what);
}

}  // namespace

struct CudaFusion::Impl {
  const carve::Carver& carver;
  thin::ThinOptions thin_options;
  Eigen::Vector3i dims;
  int words_per_row = 0;
  // Carving.
  std::vector<DeviceBuffer>
      masks;  // per camera: width x height bytes, only foreground boxes written
  DeviceBuffer cams_dev, mask_views_dev, centres, hull_dev;
  std::vector<int> present;
  std::vector<carve::CameraParams> cams_host;
  std::vector<carve::MaskView> mask_views_host;
  // CK3.
  detail::DeviceVolume vol;
  DeviceBuffer rows, flags, border[2], codes, deleted, k_list, counters, tables, simple_lut,
      tbar_lut;
  std::vector<uint64_t> staging;  // padded rows on the host
  GpuStageTimes carve_times, thin_times;
  Event e0, e1, e2, e3;

  Impl(const carve::Carver& c, const thin::ThinOptions& o)
      : carver(c), thin_options(o), dims(c.grid().dims) {}
};

CudaFusion::CudaFusion(const carve::Carver& carver, const thin::ThinOptions& thin_options) {
  const DeviceInfo device = probe_device();
  HULLPOSE_THROW_UNLESS(device.available, "CUDA backend: " << device.reason);
  check(cudaSetDevice(0), "cudaSetDevice(0)");
  impl_ = std::make_unique<Impl>(carver, thin_options);
  Impl& m = *impl_;
  const Eigen::Vector3i d = m.dims;
  const size_t ncam = carver.projectors().size();

  // Carving: masks, camera tables, voxel centres per axis (the CPU's own doubles), the hull.
  m.masks.resize(ncam);
  for (size_t c = 0; c < ncam; ++c) {
    const auto& p = carver.projectors()[c].params();
    m.masks[c].allocate(static_cast<size_t>(p.width) * static_cast<size_t>(p.height),
                        "mask buffer");
  }
  m.cams_dev.allocate(ncam * sizeof(carve::CameraParams), "camera table");
  m.mask_views_dev.allocate(ncam * sizeof(carve::MaskView), "mask table");
  m.present.reserve(ncam);
  m.cams_host.reserve(ncam);
  m.mask_views_host.reserve(ncam);
  std::vector<double> centres;
  for (int x = 0; x < d.x(); ++x) centres.push_back(carver.grid().centre_mm({x, 0, 0}).x());
  for (int y = 0; y < d.y(); ++y) centres.push_back(carver.grid().centre_mm({0, y, 0}).y());
  for (int z = 0; z < d.z(); ++z) centres.push_back(carver.grid().centre_mm({0, 0, z}).z());
  m.centres.allocate(centres.size() * sizeof(double), "voxel centres");
  upload(m.centres.as<void>(), centres.data(), m.centres.bytes(), "voxel centres");
  m.words_per_row = (d.x() + 63) / 64;
  m.hull_dev.allocate(static_cast<size_t>(m.words_per_row) * d.y() * d.z() * sizeof(uint64_t),
                      "hull");
  check(cudaMemset(m.hull_dev.as<void>(), 0, m.hull_dev.bytes()), "hull clear");

  // CK3: the padded volume of the whole grid, lists sized for every voxel, the LUTs.
  detail::DeviceVolume& v = m.vol;
  v.px = d.x() + 4;
  v.py = d.y() + 4;
  v.pz = d.z() + 4;
  v.shift = std::bit_width(static_cast<unsigned>(v.px - 1));
  v.mask = (1u << v.shift) - 1;
  v.words = static_cast<uint32_t>((v.px + 63) / 64 + 1);
  const uint64_t padded = (static_cast<uint64_t>(v.py) * static_cast<uint64_t>(v.pz)) << v.shift;
  HULLPOSE_THROW_UNLESS(padded < (uint64_t{1} << 31),
                        "CUDA backend: grid " << d.transpose() << " too large");
  auto offset = [&](int dx, int dy, int dz) { return dx + (dy + v.py * dz) * (1 << v.shift); };
  for (int b = 0; b < 27; ++b) v.off27[b] = offset(b % 3 - 1, b / 3 % 3 - 1, b / 9 - 1);
  for (int dir = 0; dir < 6; ++dir) {
    const int axis = thin::ck3::direction_axis(dir), sign = thin::ck3::direction_sign(dir);
    v.faces[dir] = offset(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
  }
  const size_t row_words = static_cast<size_t>(v.py) * static_cast<size_t>(v.pz) * v.words;
  m.rows.allocate(row_words * sizeof(uint64_t), "bit volume");
  m.flags.allocate(padded * sizeof(uint32_t), "flags");
  v.rows = m.rows.as<uint64_t>();
  v.flags = m.flags.as<uint32_t>();
  const size_t voxels = static_cast<size_t>(d.prod());
  for (auto* b : {&m.border[0], &m.border[1], &m.codes, &m.deleted, &m.k_list})
    b->allocate(voxels * sizeof(uint32_t), "voxel list");
  m.counters.allocate(sizeof(detail::Ck3Counters), "counters");
  m.simple_lut.allocate(sizeof(uint64_t) << 20, "simple-point LUT");
  upload(m.simple_lut.as<void>(), hullpose_simple_lut, m.simple_lut.bytes(), "simple-point LUT");
  m.tbar_lut.allocate(size_t{1} << 18, "T-bar LUT");
  upload(m.tbar_lut.as<void>(), hullpose_tbar_lut, m.tbar_lut.bytes(), "T-bar LUT");
  thin::ck3::RuleTables t = thin::ck3::host_rule_tables();
  t.simple_lut = m.simple_lut.as<uint64_t>();
  t.tbar_lut = m.tbar_lut.as<uint8_t>();
  m.tables.allocate(sizeof t, "rule tables");
  upload(m.tables.as<void>(), &t, sizeof t, "rule tables");
  m.staging.resize(row_words);
}

CudaFusion::~CudaFusion() = default;

const GpuStageTimes& CudaFusion::carve_times() const {
  return impl_->carve_times;
}
const GpuStageTimes& CudaFusion::thin_times() const {
  return impl_->thin_times;
}

void CudaFusion::carve(std::span<const cv::Mat> views, fusion::BitGrid& hull,
                       carve::CarveReport& report, std::span<const PixelRoi> fg_boxes) {
  Impl& m = *impl_;
  if (!m.carver.begin_carve(views, fg_boxes, hull, report, m.present)) return;
  m.e0.record();
  m.cams_host.clear();
  m.mask_views_host.clear();
  for (int c : m.present) {
    const cv::Mat& mask = views[static_cast<size_t>(c)];
    const cv::Rect box = carve::foreground_box(mask, fg_boxes, static_cast<size_t>(c));
    auto* dev = m.masks[static_cast<size_t>(c)].as<uint8_t>();
    const size_t pitch = static_cast<size_t>(mask.cols);
    if (box.area() > 0)
      check(cudaMemcpy2D(dev + static_cast<size_t>(box.y) * pitch + static_cast<size_t>(box.x),
                         pitch, mask.ptr<uint8_t>(box.y) + box.x, mask.step[0],
                         static_cast<size_t>(box.width), static_cast<size_t>(box.height),
                         cudaMemcpyHostToDevice),
            "mask upload");
    m.cams_host.push_back(m.carver.projectors()[static_cast<size_t>(c)].params());
    m.mask_views_host.push_back({dev, pitch, box.x, box.y, box.x + box.width, box.y + box.height});
  }
  upload(m.cams_dev.as<void>(), m.cams_host.data(),
         m.cams_host.size() * sizeof(carve::CameraParams), "camera table");
  upload(m.mask_views_dev.as<void>(), m.mask_views_host.data(),
         m.mask_views_host.size() * sizeof(carve::MaskView), "mask table");
  m.e1.record();
  detail::CarveArgs a;
  a.cams = m.cams_dev.as<carve::CameraParams>();
  a.masks = m.mask_views_dev.as<carve::MaskView>();
  a.ncams = static_cast<int>(m.present.size());
  a.tolerance = m.carver.options().tolerance;
  a.centre_x = m.centres.as<double>();
  a.centre_y = a.centre_x + m.dims.x();
  a.centre_z = a.centre_y + m.dims.y();
  a.nx = m.dims.x();
  a.ny = m.dims.y();
  a.nz = m.dims.z();
  a.hull = m.hull_dev.as<uint32_t>();
  a.words_per_row = m.words_per_row;
  check_launch(detail::launch_carve(a), "carve kernel");
  m.e2.record();
  download(hull.words().data(), m.hull_dev.as<void>(), hull.words().size() * sizeof(uint64_t),
           "hull download");
  m.e3.record();
  m.e3.wait();
  m.carve_times = {m.e1.ms_since(m.e0), m.e2.ms_since(m.e1), m.e3.ms_since(m.e2)};
  report.voxels = hull.count();
}

thin::ThinStats CudaFusion::thin(fusion::BitGrid& volume) {
  Impl& m = *impl_;
  HULLPOSE_THROW_UNLESS(volume.dims() == m.dims, "CUDA thinning: volume dims "
                                                     << volume.dims().transpose()
                                                     << " differ from the grid's "
                                                     << m.dims.transpose());
  detail::DeviceVolume& v = m.vol;
  thin::ThinStats stats;
  stats.initial_voxels = volume.count();
  // Pad on the host (2 background voxels on every side), as the CPU's working volume.
  std::fill(m.staging.begin(), m.staging.end(), uint64_t{0});
  const int gw = volume.words_per_row();
  for (int z = 0; z < m.dims.z(); ++z)
    for (int y = 0; y < m.dims.y(); ++y) {
      const uint64_t* src = volume.row(y, z);
      uint64_t* dst = m.staging.data() + (static_cast<size_t>(z + 2) * static_cast<size_t>(v.py) +
                                          static_cast<size_t>(y) + 2) *
                                             v.words;
      for (int w = 0; w < gw; ++w) {
        dst[w] |= src[w] << 2;
        dst[w + 1] |= src[w] >> 62;
      }
    }
  m.e0.record();
  upload(m.rows.as<void>(), m.staging.data(), m.rows.bytes(), "volume upload");
  check(cudaMemset(m.flags.as<void>(), 0, m.flags.bytes()), "flags clear");
  check(cudaMemset(m.counters.as<void>(), 0, sizeof(detail::Ck3Counters)), "counters clear");
  m.e1.record();
  const auto* tables = m.tables.as<thin::ck3::RuleTables>();
  auto* counters = m.counters.as<detail::Ck3Counters>();
  check_launch(detail::launch_ck3_border(v, m.border[0].as<uint32_t>(), counters), "border kernel");
  detail::Ck3Counters host{};
  download(&host, counters, sizeof host, "counters");
  uint32_t n = host.next;
  int cur = 0, iterations = 0;
  const thin::CurveRule rule = m.thin_options.rule;
  while (n > 0) {
    const uint32_t* border = m.border[cur].as<uint32_t>();
    uint32_t* codes = m.codes.as<uint32_t>();
    // Reset next, deleted and constrained; k_total runs on.
    check(cudaMemset(counters, 0, 3 * sizeof(uint32_t)), "counters reset");
    check_launch(detail::launch_ck3_classify(v, tables, rule, border, n, codes), "classify kernel");
    auto pass = [&](detail::Ck3Pass p) {
      check_launch(detail::launch_ck3_pass(p, v, tables, border, n, codes), "pass kernel");
    };
    if (rule == thin::CurveRule::kCk3) {
      pass(detail::Ck3Pass::kCk3Surface);
      pass(detail::Ck3Pass::kCk3Candidate);
    } else if (rule == thin::CurveRule::kIsthmus) {
      pass(detail::Ck3Pass::kIsthmusPairs);
      pass(detail::Ck3Pass::kIsthmusEdges);
      pass(detail::Ck3Pass::kIsthmusSettle);
    }
    pass(detail::Ck3Pass::kLevel2);
    pass(detail::Ck3Pass::kLevel1);
    check_launch(detail::launch_ck3_level0(v, tables, m.thin_options.zero_clique, border, n, codes,
                                           m.deleted.as<uint32_t>(), counters),
                 "level-0 kernel");
    check_launch(detail::launch_ck3_settle(v, border, n, m.deleted.as<uint32_t>(), n,
                                           m.border[1 - cur].as<uint32_t>(),
                                           m.k_list.as<uint32_t>(), counters),
                 "settle kernels");
    download(&host, counters, sizeof host, "counters");
    stats.visited += n;
    cur = 1 - cur;
    n = host.next;
    ++iterations;
    // Stable when nothing was deleted and K did not grow (as the CPU thinner).
    if ((host.deleted == 0 && host.constrained == 0) ||
        (m.thin_options.max_iterations > 0 && iterations >= m.thin_options.max_iterations))
      break;
  }
  m.e2.record();
  download(m.staging.data(), m.rows.as<void>(), m.rows.bytes(), "volume download");
  m.e3.record();
  m.e3.wait();
  m.thin_times = {m.e1.ms_since(m.e0), m.e2.ms_since(m.e1), m.e3.ms_since(m.e2)};
  const int tail = m.dims.x() % 64;
  const uint64_t last_mask = tail == 0 ? ~uint64_t{0} : (uint64_t{1} << tail) - 1;
  for (int z = 0; z < m.dims.z(); ++z)
    for (int y = 0; y < m.dims.y(); ++y) {
      uint64_t* dst = volume.row(y, z);
      const uint64_t* src =
          m.staging.data() +
          (static_cast<size_t>(z + 2) * static_cast<size_t>(v.py) + static_cast<size_t>(y) + 2) *
              v.words;
      for (int w = 0; w < gw; ++w) dst[w] = src[w] >> 2 | src[w + 1] << 62;
      dst[gw - 1] &= last_mask;
    }
  stats.iterations = iterations;
  stats.final_voxels = volume.count();
  stats.constrained = host.k_total;
  return stats;
}

}  // namespace hullpose::gpu
