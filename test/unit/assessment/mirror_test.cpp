// Mirror property: mirroring a scene left <-> right (y -> −y, θ -> −θ) flips Dir and the half-plane
// normals' y, and keeps t_CROSS, every distance, every predicate and CM.
#include <gtest/gtest.h>

#include <cmath>

#include "coopnav/assessment/crossing.hpp"
#include "coopnav/assessment/path_assessment.hpp"
#include "coopnav/assessment/situation.hpp"

namespace coopnav::assessment {
namespace {

Band mirror(Band b) {
  for (auto& p : b.poses) {
    p.pose.y_m = -p.pose.y_m;
    p.pose.theta_rad = -p.pose.theta_rad;
  }
  return b;
}
Eigen::Vector2d mirror(Eigen::Vector2d p) { return {p.x(), -p.y()}; }
Path2 mirror(Path2 path) {
  for (auto& p : path) p = mirror(p);
  return path;
}

struct Scene {
  Band robot, human;
  Path2 reference;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> observed;  // (human, robot) at 10 Hz
};

// A bending human band (it swerves right of its path y = 0.5) and a robot band veering left,
// with unequal ΔT; observations of a human that drifts away and a robot that passes on its left.
Scene makeScene() {
  Scene s;
  for (int i = 0; i <= 120; ++i) {
    const double t = 0.1 * i;
    s.robot.poses.push_back({t, {0.9 * t, 0.3 * std::sin(0.25 * t), 0.1}});
  }
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.3 * i;
    const double y = 0.5 - 0.6 * std::exp(-std::pow(t - 6.0, 2) / 4.0);
    s.human.poses.push_back({t, {12.0 - t, y, M_PI - 0.05}});
  }
  s.reference = {{12.0, 0.5}, {0.0, 0.5}};
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.1 * i;
    s.observed.push_back({{12.0 - t, 0.5 + 0.1 * t}, {0.9 * t, -0.4}});
  }
  return s;
}

TEST(Mirror, LeftRightMirrorFlipsDirAndKeepsEverythingElse) {
  const Scene a = makeScene();
  Scene b;
  b.robot = mirror(a.robot);
  b.human = mirror(a.human);
  b.reference = mirror(a.reference);
  for (const auto& [h, r] : a.observed) b.observed.push_back({mirror(h), mirror(r)});

  const CrossingInfo ca = computeCrossing(a.robot, a.human);
  const CrossingInfo cb = computeCrossing(b.robot, b.human);
  ASSERT_EQ(ca.status, CrossingStatus::kOk) << ca.reason;
  ASSERT_EQ(cb.status, CrossingStatus::kOk);
  ASSERT_NE(ca.dir, Side::kUndefined);
  EXPECT_EQ(cb.dir, opposite(ca.dir));
  EXPECT_NEAR(*cb.t_cross_s, *ca.t_cross_s, 1e-12);
  EXPECT_EQ(cb.i_star, ca.i_star);
  EXPECT_TRUE(cb.cp_h.isApprox(mirror(ca.cp_h)));
  EXPECT_TRUE(cb.cp_r.isApprox(mirror(ca.cp_r)));

  const auto qa = halfPlaneQueries(ca);
  const auto qb = halfPlaneQueries(cb);
  ASSERT_TRUE(qa && qb);
  EXPECT_TRUE(qb->human.normal.isApprox(mirror(qa->human.normal)));
  EXPECT_TRUE(qb->robot.normal.isApprox(mirror(qa->robot.normal)));

  // The mirrored map answers the mirrored queries with the same distances.
  const SituationAssessment sa = assessSituation(ca, a.reference, 0.8, 0.25);
  const SituationAssessment sb = assessSituation(cb, b.reference, 0.8, 0.25);
  EXPECT_NEAR(*sb.d_h_m, *sa.d_h_m, 1e-12);
  EXPECT_NEAR(*sb.d_hr_m, *sa.d_hr_m, 1e-12);
  EXPECT_EQ(sb.human_needs_to_contribute, sa.human_needs_to_contribute);
  EXPECT_EQ(sb.human_is_constrained, sa.human_is_constrained);
  EXPECT_EQ(sb.robot_is_constrained, sa.robot_is_constrained);

  PathRecorder ra, rb;
  ASSERT_TRUE(ra.start(0.0, a.reference));
  ASSERT_TRUE(rb.start(0.0, b.reference));
  for (std::size_t i = 0; i < a.observed.size(); ++i) {
    ra.observe(0.1 * i, a.observed[i].first, a.observed[i].second);
    rb.observe(0.1 * i, b.observed[i].first, b.observed[i].second);
  }
  const auto pa = ra.snapshot();
  const auto pb = rb.snapshot();
  ASSERT_EQ(pa.interaction_samples, 61u);
  EXPECT_GT(*pa.cm_window_m, 0.0);  // drifting away from a robot on the other side
  EXPECT_NEAR(*pb.cm_window_m, *pa.cm_window_m, 1e-12);
  EXPECT_EQ(pb.is_contributing_window, pa.is_contributing_window);
}

}  // namespace
}  // namespace coopnav::assessment
