// The hull tracker, the body model estimator and the One Euro filter on synthetic capsule
// bodies (capsule_hull.hpp): what each promises, checked on shapes whose answer is known.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "capsule_hull.hpp"
#include "hullpose/pose/hull_tracker.hpp"
#include "hullpose/pose/one_euro.hpp"

using namespace hullpose;
using namespace hullpose::pose;
using namespace hullpose::pose::test;

namespace {
constexpr double kStature = 1750;

// The hull of a capsule body (capsule_hull.hpp) and its surface as the tracker sees it (the
// surface reads the hull: they live together).
struct BodyHull {
  fusion::BitGrid hull;
  HullSurface surface{1000};
  BodyHull(const VoxelGridSpec& g, const JointPositions& pose, const BodyModel& model) {
    capsule_hull(g, pose, model, hull);
    surface.extract(&hull, g);
  }
  BodyHull(const BodyHull&) = delete;
  BodyHull& operator=(const BodyHull&) = delete;
};

Limbs arms_down() {
  Limbs l;
  l.l_upper_arm = {0.25, 0, -1};
  l.l_forearm = {0.2, 0.5, -1};
  l.r_upper_arm = {-0.6, 0.2, -1};
  l.r_forearm = {-0.3, 0.8, -0.4};
  l.l_thigh = {0.05, 0.3, -1};
  l.r_thigh = {-0.05, -0.2, -1};
  return l;
}
}  // namespace

TEST_CASE(
    "hull surface: the shell of a solid, subsampled, and whether it reaches the grid's edge") {
  const VoxelGridSpec g = grid_2m(32);
  fusion::BitGrid hull(g.dims);
  for (int z = 4; z < 12; ++z)
    for (int y = 4; y < 12; ++y)
      for (int x = 4; x < 12; ++x) hull.set(x, y, z);
  HullSurface all(10000), few(50);
  all.extract(&hull, g);
  few.extract(&hull, g);
  CHECK(all.points().size() == 8 * 8 * 8 - 6 * 6 * 6);  // the cube minus its interior
  CHECK(few.points().size() <= 50);
  CHECK(few.points().size() >= 40);  // an even stride, not a truncated scan
  CHECK_FALSE(all.touches_edge());
  // A ball rules itself out only when it holds an unset voxel's centre.
  CHECK_FALSE(all.excludes(g.centre_mm({8, 8, 8}), g.voxel_mm));
  CHECK(all.excludes(g.centre_mm({2, 2, 2}), 0.1 * g.voxel_mm));
  const Eigen::Vector3d corner =
      g.centre_mm({2, 2, 2}) + Eigen::Vector3d::Constant(0.45 * g.voxel_mm);
  CHECK_FALSE(all.excludes(corner, 0.5 * g.voxel_mm));  // no voxel centre within the ball
  CHECK(all.excludes(corner, g.voxel_mm));
  // The cube's top face (voxels z 4..11), over its middle and not beside it.
  const Eigen::Vector2d middle = g.centre_mm({8, 8, 0}).head<2>();
  CHECK(all.top_mm(middle, 1.5 * g.voxel_mm) == Approx(g.origin_mm.z() + 12 * g.voxel_mm));
  CHECK(std::isnan(all.top_mm(g.centre_mm({20, 20, 0}).head<2>(), 1.5 * g.voxel_mm)));
  hull.set(0, 8, 8);
  all.extract(&hull, g);
  CHECK(all.touches_edge());
  all.extract(nullptr, g);
  CHECK(all.empty());
}

TEST_CASE("hull surface: the nearest point is the full scan's, at every stride") {
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel model = BodyModel::from_stature(kStature);
  const JointPositions body = stick_figure(kStature, arms_down(), {20, 0, 0, 0});
  BodyHull scene(g, body, model);
  HullSurface& surface = scene.surface;
  const auto points = surface.points();
  REQUIRE(points.size() > 500);
  // The full scan: the first of the nearest among points 0, stride, 2 stride, ...
  auto scan = [&](const Eigen::Vector3d& mm, size_t stride) {
    const Eigen::Vector3f p = mm.cast<float>();
    size_t best = 0;
    for (size_t k = 0; k < points.size(); k += stride)
      if ((points[k] - p).squaredNorm() < (points[best] - p).squaredNorm()) best = k;
    return points[best].cast<double>();
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-1200, 1200), z(-300, 2300);
  int n = 0;
  for (size_t stride : {1, 2, 3, 7}) {
    for (int i = 0; i < 300; ++i) {
      // Anywhere in and around the grid, and exactly on surface points (ties at distance 0).
      const Eigen::Vector3d q = i % 10 == 0
                                    ? points[static_cast<size_t>(i) % points.size()].cast<double>()
                                    : Eigen::Vector3d(xy(rng), xy(rng), z(rng));
      n += surface.nearest(q, stride) == scan(q, stride);
    }
  }
  CHECK(n == 4 * 300);
}

TEST_CASE("tracking pulls a displaced model back onto the hull of the true pose") {
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel model = BodyModel::from_stature(kStature);
  JointPositions truth = stick_figure(kStature, arms_down(), {20, 0, 0, 0});
  for (auto& p : truth) p.z() += 100;
  BodyHull scene(g, truth, model);
  HullSurface& surface = scene.surface;
  // Start 60 mm off sideways with the left arm 25 degrees out.
  JointPositions start = truth;
  for (auto& p : start) p += Eigen::Vector3d(60, -30, 0);
  HullTracker tracker;
  tracker.start(start);
  const double before = mean_error(start, truth);
  double after = 0;
  for (int f = 0; f < 4; ++f) after = mean_error(tracker.track(surface, model, {}).joints, truth);
  INFO("mean joint error " << before << " -> " << after << " mm");
  CHECK(after < 0.35 * before);
  CHECK(after < 25);
  const HullScore s = tracker.result().score;
  CHECK(s.inside > 0.9);
  CHECK(s.explained > 0.8);
  // The pose that explains the hull scores higher than a displaced one.
  CHECK(tracker.score(surface, model, truth).value() >
        tracker.score(surface, model, start).value());
}

TEST_CASE("the hull never contradicts the true pose: thin limbs, tips, any voxel size") {
  // A limb thinner than the voxels can fall between their centres and be carved away, and a tip
  // joint lies on the body's surface with voxel centres outside the body beside it. Neither is
  // evidence against the pose: the score samples the capsules' axes, and a sample counts as
  // outside only where the voxel centre nearest to it is unset and within the capsule's radius.
  const BodyModel model = BodyModel::from_stature(kStature);
  const JointPositions truth = stick_figure(kStature, arms_down(), {0, 0, 0, 0});
  HullTracker tracker;
  for (int res : {24, 32, 64, 128}) {
    const VoxelGridSpec g = grid_2m(res);
    BodyHull scene(g, truth, model);
    HullSurface& surface = scene.surface;
    INFO(res << "^3, voxel " << g.voxel_mm << " mm");
    CHECK(tracker.score(surface, model, truth).inside == 1.0);
    // ...while a pose beside the body is contradicted.
    JointPositions beside = truth;
    for (auto& p : beside) p.x() += 400;
    CHECK(tracker.score(surface, model, beside).inside < 0.5);
  }
}

TEST_CASE("an arm the previous pose had out in the air is pulled into the hull") {
  // The salsa clips' first frames: the arms go from spread to folded against the body between
  // two frames, so the predicted arm lies where the hull is empty and no surface point is nearer
  // to it than to the torso. Without the model-to-hull pull it stays out there for good; with
  // it the arm comes into the hull (not yet onto the true arm: the nearest hull is the
  // shoulder's, and the bottom-up path has to re-acquire the rest).
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel model = BodyModel::from_stature(kStature);
  const JointPositions truth = stick_figure(kStature, arms_down(), {0, 0, 0, 0});
  Limbs spread = arms_down();
  spread.l_upper_arm = {1, 0, 0};
  spread.l_forearm = {1, 0, 0};
  const JointPositions start = stick_figure(kStature, spread, {0, 0, 0, 0});
  BodyHull scene(g, truth, model);
  HullSurface& surface = scene.surface;
  auto hand_error = [&](const JointPositions& p) {
    return (p[index(Joint::LHand)] - truth[index(Joint::LHand)]).norm();
  };
  auto track = [&](double inside_weight) {
    TrackParams params;
    params.inside_weight = inside_weight;
    HullTracker tracker(params);
    tracker.start(start);
    for (int f = 0; f < 10; ++f) tracker.track(surface, model, {});
    return tracker.result();
  };
  const TrackResult pulled = track(TrackParams{}.inside_weight), left_out = track(0);
  INFO("left hand error " << hand_error(start) << " mm at the start, " << hand_error(pulled.joints)
                          << " mm tracked, " << hand_error(left_out.joints)
                          << " mm without the pull");
  CHECK(pulled.score.inside > 0.95);
  CHECK(hand_error(pulled.joints) < 0.5 * hand_error(start));
  CHECK(pulled.score.value() > left_out.score.value());
  CHECK(left_out.score.inside < 0.9);
  CHECK(hand_error(left_out.joints) > 0.95 * hand_error(start));
}

TEST_CASE("a limb the hull does not show is kept inside the hull, with low confidence") {
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel model = BodyModel::from_stature(kStature);
  const JointPositions truth = stick_figure(kStature, arms_down(), {0, 0, 0, 0});
  BodyHull scene(g, truth, model);
  HullSurface& surface = scene.surface;
  HullTracker tracker;
  tracker.start(truth);
  tracker.track(surface, model, {});
  const float shown = tracker.result().confidence[index(Joint::RHand)];
  // The right forearm and hand vanish from the hull (hidden from a camera: a limb merged into
  // the torso stays inside the hull and is not moved). The hull has no volume where they were:
  // they are drawn to the nearest hull, the right upper arm's, and explain little there.
  capsule_hull(g, truth, model, scene.hull, {8, 10});
  surface.extract(&scene.hull, g);
  for (int f = 0; f < 10; ++f) tracker.track(surface, model, {});
  const TrackResult& r = tracker.result();
  auto error = [&](Joint j) { return (r.joints[index(j)] - truth[index(j)]).norm(); };
  INFO("right hand moved " << error(Joint::RHand) << " mm, left " << error(Joint::LHand) << " mm");
  CHECK(r.score.inside >= 0.95);
  CHECK(error(Joint::LHand) < 30);
  CHECK(r.confidence[index(Joint::RHand)] < 0.6f * shown);
  CHECK(r.confidence[index(Joint::RHand)] < 0.6f * r.confidence[index(Joint::LHand)]);
  CHECK(r.confidence[index(Joint::LHand)] > 0.8f * shown);
}

namespace {
// The shoulders and arms of an upright pose turned about the vertical through the chest.
JointPositions turn_girdle(const JointPositions& pose, double deg) {
  JointPositions turned = pose;
  const Eigen::Vector3d chest = pose[index(Joint::Chest)];
  const Eigen::AngleAxisd turn(deg * std::numbers::pi / 180, Eigen::Vector3d::UnitZ());
  for (Joint j : {Joint::LSho, Joint::RSho, Joint::LElb, Joint::RElb, Joint::LHand, Joint::RHand,
                  Joint::LFTip, Joint::RFTip})
    turned[index(j)] = chest + turn * (pose[index(j)] - chest);
  return turned;
}
}  // namespace

TEST_CASE("torso_twist reads the shoulder line against the hip line; swap_arms swaps labels") {
  const JointPositions upright = stick_figure(kStature, arms_down());
  CHECK(std::abs(torso_twist(upright)) < 1e-9);
  // The girdle and arms turned 30 deg about the spine (left shoulder forward: +y is forward,
  // +x the subject's left, so +30 about up).
  const JointPositions turned = turn_girdle(upright, 30);
  CHECK(torso_twist(turned) * 180 / std::numbers::pi == Approx(30).margin(1e-6));
  JointPositions swapped = upright;
  swap_arms(swapped);
  CHECK(std::abs(torso_twist(swapped)) * 180 / std::numbers::pi == Approx(180).margin(1e-6));
  CHECK(swapped[index(Joint::LHand)] == upright[index(Joint::RHand)]);
  CHECK(swapped[index(Joint::Head)] == upright[index(Joint::Head)]);
}

TEST_CASE(
    "the shoulder girdle is kept within the trunk's twist: turned back, or its arms swapped "
    "beyond 90 deg") {
  // The hull cannot tell the arms apart, and the chest's capsule is round about the spine: a
  // girdle turned round it explains the hull as well as the true one.
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel model = BodyModel::from_stature(kStature);
  const JointPositions truth = stick_figure(kStature, arms_down());
  BodyHull scene(g, truth, model);
  HullSurface& surface = scene.surface;
  auto track = [&](const JointPositions& start, const TrackParams& params) {
    HullTracker tracker(params);
    tracker.start(start);
    for (int f = 0; f < 10; ++f) tracker.track(surface, model, {});
    return tracker.result().joints;
  };
  auto arm_error = [&](const JointPositions& p) {
    double e = 0;
    for (Joint j : {Joint::LSho, Joint::LElb, Joint::LHand, Joint::RSho, Joint::RElb, Joint::RHand})
      e += (p[index(j)] - truth[index(j)]).norm() / 6;
    return e;
  };
  auto twist_deg = [](const JointPositions& p) { return torso_twist(p) * 180 / std::numbers::pi; };

  SECTION("arms labelled the wrong way round (twist 180 deg) are swapped back") {
    JointPositions start = truth;
    swap_arms(start);
    const JointPositions tracked = track(start, {});
    INFO("arm joints off by " << arm_error(start) << " mm at the start, " << arm_error(tracked)
                              << " mm tracked");
    CHECK(arm_error(tracked) < 25);
    CHECK(std::abs(twist_deg(tracked)) < 10);
  }
  SECTION("a girdle turned 80 deg is turned back to the limit") {
    const JointPositions start = turn_girdle(truth, 80);
    TrackParams unlimited;
    unlimited.max_twist_deg = 180;
    const JointPositions limited = track(start, {}), free = track(start, unlimited);
    INFO("twist " << twist_deg(start) << " deg at the start, " << twist_deg(limited)
                  << " deg tracked, " << twist_deg(free) << " deg without the limit");
    CHECK(std::abs(twist_deg(limited)) < 62);
    CHECK(std::abs(twist_deg(free)) > 75);
  }
}

TEST_CASE("the hips are not folded together: pulled to min_hip_ratio of the hip bones apart") {
  // A hull whose pelvis and legs are one narrow column (both hip joints under the spine, the
  // legs together) asks a model started with the hips apart to fold them onto each other.
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel model = BodyModel::from_stature(kStature);
  const JointPositions start = stick_figure(kStature, arms_down());
  JointPositions folded = start;
  const Eigen::Vector3d mid = 0.5 * (start[index(Joint::LHip)] + start[index(Joint::RHip)]);
  for (const Limb& leg : {kLimbs[2], kLimbs[3]}) {
    const Eigen::Vector3d shift = mid - start[index(leg.root())];
    for (int k = 0; k < leg.size; ++k) folded[index(leg.joints[static_cast<size_t>(k)])] += shift;
  }
  BodyHull scene(g, folded, model);
  const double two_hip_bones = model.length_mm[static_cast<size_t>(bone_to(Joint::LHip))] +
                               model.length_mm[static_cast<size_t>(bone_to(Joint::RHip))];
  auto hips_apart = [&](const TrackParams& params) {
    HullTracker tracker(params);
    tracker.start(start);
    for (int f = 0; f < 10; ++f) tracker.track(scene.surface, model, {});
    const JointPositions& x = tracker.result().joints;
    return (x[index(Joint::RHip)] - x[index(Joint::LHip)]).norm() / two_hip_bones;
  };
  TrackParams unlimited;
  unlimited.min_hip_ratio = 0;
  const double held = hips_apart({}), free = hips_apart(unlimited);
  INFO("hips apart / two hip bones: " << held << " held, " << free << " without the floor");
  // A pull, not a hard limit: the hull's points pull the other way.
  CHECK(held > 0.85 * TrackParams{}.min_hip_ratio);
  CHECK(free < 0.5 * TrackParams{}.min_hip_ratio);
}

namespace {
// The evidence of `points` surface points at the cap of `bone` that lies `target_mm` from its
// parent, linearised at the model's current lengths (r = current - target, dr/dlength = 1).
LengthEvidence cap_at(const BodyModel& m, int bone, double target_mm, double points) {
  LengthEvidence e;
  e.at_mm = m.length_mm;
  e.hessian(bone, bone) = points;
  e.gradient(bone) = points * (m.length_mm[bone] - target_mm);
  e.measured = true;
  return e;
}
}  // namespace

TEST_CASE("the body model converges to what the frames measure, then is held") {
  BodyModelParams p;
  p.converge_frames = 10;
  BodyModelEstimator est(p);
  est.reset(1600);
  CHECK(est.version() == 0);
  const int thigh = 16, upper_arm = 5;
  std::array<double, kNumBones> radius;
  radius.fill(std::nan(""));
  // The thigh shows 10 % more than Table 6.7 at 1600 mm on every frame; the upper arm shows
  // nothing (a frame with no evidence on a bone leaves it at the prior, not diluted).
  const double target = 0.224 * 1600 * 1.1;
  for (int f = 0; f < 9; ++f) est.add(cap_at(est.model(), thigh, target, 30), radius);
  CHECK(est.model().length_mm[thigh] == Approx(target).epsilon(0.02));
  CHECK(est.model().length_mm[thigh + 1] == est.model().length_mm[thigh]);  // one body: both thighs
  CHECK(est.model().length_mm[upper_arm] == Approx(0.162 * 1600));
  CHECK(!est.held());
  est.add(cap_at(est.model(), thigh, target, 30), radius);
  // Held after converge_frames: no measurement and no reset changes a length again.
  CHECK(est.held());
  CHECK(est.version() == 1);
  const BodyModel held = est.model();
  est.add(cap_at(est.model(), thigh, 10 * target, 1000), radius);
  est.reset(1000);
  for (int b = 0; b < kNumBones; ++b) CHECK(est.model().length_mm[b] == held.length_mm[b]);
}

TEST_CASE("a frame's length evidence pulls in a bone that reaches beyond the hull") {
  // A forearm 30 % too long: the hand it carries sticks out where the hull has no volume. No
  // surface point lies out there, so the surface points' half of the evidence cannot say
  // "shorter"; the capsule axis samples the hull rules out can (HullTracker::measure_lengths).
  const VoxelGridSpec g = grid_2m(128);
  const BodyModel body = BodyModel::from_stature(kStature);
  const JointPositions truth = stick_figure(kStature, arms_down(), {0, 0, 0, 0});
  BodyHull scene(g, truth, body);
  HullSurface& surface = scene.surface;
  const int forearm = 8;  // RElb -> RHand: held forward, its extension is in the air
  BodyModel long_arm = body;
  long_arm.length_mm[forearm] *= 1.3;
  JointPositions pose = truth;
  impose_bone_lengths(pose, long_arm.length_mm);
  TrackParams params;
  params.iterations = 0;  // the evidence at this pose, not at a fit of it
  HullTracker tracker(params);
  tracker.start(pose);
  tracker.track(surface, long_arm, {});
  const LengthEvidence& e = tracker.length_evidence(surface, long_arm);
  REQUIRE(e.measured);
  CHECK(e.hessian(forearm, forearm) > 1);  // the frame measures that length (~0 without the half)
  // The frame's Gauss-Newton step on that length, the others held.
  const double step = -e.gradient(forearm) / e.hessian(forearm, forearm);
  const double excess = long_arm.length_mm[forearm] - body.length_mm[forearm];
  INFO("forearm " << long_arm.length_mm[forearm] << " mm, true " << body.length_mm[forearm]
                  << ", step " << step);
  CHECK(step < -0.3 * excess);
  CHECK(step > -1.5 * excess);
}

TEST_CASE("a subject seen in few confident frames is held after hold_after_frames") {
  BodyModelParams p;
  BodyModelEstimator est(p);
  est.reset(1700);
  std::array<double, kNumBones> radius;
  radius.fill(std::nan(""));
  // One confident frame in five: enough for the hold (min_hold_frames), too few to converge.
  int confident = 0;
  for (int f = 0; f < p.hold_after_frames - 1; ++f) {
    est.tick();
    if (f % 5 == 0) {
      est.add(LengthEvidence{}, radius);
      ++confident;
    }
  }
  REQUIRE(confident >= p.min_hold_frames);
  REQUIRE(confident < p.converge_frames);
  CHECK(!est.held());
  est.tick();
  CHECK(est.version() == 1);
}

TEST_CASE("lean_head_on_trunk turns the head halfway to the trunk's axis, about the Head joint") {
  const JointPositions upright = stick_figure(kStature, arms_down());
  const Eigen::Vector3d head = upright[index(Joint::Head)];
  const double len = (upright[index(Joint::HeadTop)] - head).norm();
  // The head tipped 60 deg forward (+y) on an upright trunk.
  JointPositions tipped = upright;
  tipped[index(Joint::HeadTop)] = head + len * Eigen::Vector3d(0, std::sin(std::numbers::pi / 3),
                                                               std::cos(std::numbers::pi / 3));
  JointPositions leaned = tipped;
  lean_head_on_trunk(leaned, 0.5);
  const Eigen::Vector3d d = leaned[index(Joint::HeadTop)] - head;
  CHECK(d.norm() == Approx(len).margin(1e-9));
  CHECK(std::atan2(d.y(), d.z()) * 180 / std::numbers::pi == Approx(30).margin(1e-9));
  for (int j = 0; j < kNumJoints; ++j)
    if (j != index(Joint::HeadTop)) CHECK(leaned[j] == tipped[j]);
  // Weight 0 keeps the head as it is; 1 puts it on the trunk's axis (here the vertical).
  JointPositions kept = tipped, onto = tipped;
  lean_head_on_trunk(kept, 0);
  lean_head_on_trunk(onto, 1);
  CHECK((kept[index(Joint::HeadTop)] - tipped[index(Joint::HeadTop)]).norm() < 1e-9);
  CHECK((onto[index(Joint::HeadTop)] - (head + Eigen::Vector3d(0, 0, len))).norm() < 1e-9);
  // A head pointing straight against the trunk has no mean direction: left as it is.
  JointPositions against = upright;
  against[index(Joint::HeadTop)] = head - Eigen::Vector3d(0, 0, len);
  const JointPositions before = against;
  lean_head_on_trunk(against, 0.5);
  CHECK(against[index(Joint::HeadTop)] == before[index(Joint::HeadTop)]);
}

TEST_CASE("impose_bone_lengths keeps directions and gives the model's lengths") {
  const BodyModel m = BodyModel::from_stature(1700);
  JointPositions pose = stick_figure(1700, arms_down());
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 8);
  for (auto& j : pose) {
    const double x = noise(rng), y = noise(rng), z = noise(rng);  // named: a defined order
    j += Eigen::Vector3d(x, y, z);
  }
  const JointPositions given = pose;
  impose_bone_lengths(pose, m.length_mm);
  CHECK(pose[index(Joint::Chest)] == given[index(Joint::Chest)]);
  for (int b = 0; b < kNumBones; ++b) {
    const int pa = index(kBones[b].parent), c = index(kBones[b].child);
    CHECK((pose[c] - pose[pa]).norm() == Approx(m.length_mm[b]).margin(1e-9));
    CHECK((pose[c] - pose[pa]).normalized().dot((given[c] - given[pa]).normalized()) ==
          Approx(1.0).margin(1e-12));
  }
}

TEST_CASE(
    "One Euro: off by default; on, a still joint is smoothed, a moving one lags less than "
    "a frame") {
  std::array<Eigen::Vector3d, 1> passed{Eigen::Vector3d(1, 2, 3)};
  OneEuroFilter off;
  off.apply(passed, 1.0 / 30);
  passed[0] = Eigen::Vector3d(40, 50, 60);
  off.apply(passed, 1.0 / 30);
  CHECK(passed[0] == Eigen::Vector3d(40, 50, 60));
  const OneEuroParams on{.min_cutoff_hz = 1.5};
  OneEuroFilter still_filter(on), moving_filter(on);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 3);
  double raw = 0, filtered = 0;
  const double dt = 1.0 / 30;
  double lag_mm = 0;
  for (int f = 0; f < 300; ++f) {
    const double nx = noise(rng), ny = noise(rng), nz = noise(rng);  // named: a defined order
    std::array<Eigen::Vector3d, 1> still{Eigen::Vector3d(nx, ny, nz)};
    raw += still[0].squaredNorm();
    still_filter.apply(still, dt);
    if (f >= 30) filtered += still[0].squaredNorm();
    // 1.5 m/s: 50 mm per frame.
    std::array<Eigen::Vector3d, 1> moving{Eigen::Vector3d(50.0 * f, 0, 0)};
    moving_filter.apply(moving, dt);
    lag_mm = 50.0 * f - moving[0].x();
  }
  CHECK(std::sqrt(filtered / 270) < 0.5 * std::sqrt(raw / 300));
  CHECK(lag_mm >= 0);
  CHECK(lag_mm < 50);  // under one frame's motion
}
