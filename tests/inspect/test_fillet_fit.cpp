#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <random>
#include <string>

#include "ewis/core/robust.hpp"
#include "ewis/inspect/fillet_fit.hpp"
#include "paths.hpp"

using namespace ewis;

namespace {

// Surface points of a tube swept along a line-arc-line centreline in the xy plane (legs of `leg_mm`, arc of
// radius R turning by `turn_deg`), seen from a sensor 600 mm above: only the upper half, with Gaussian noise of
// `noise_mm` along the sensor's rays and `outlier_fraction` of points scattered inside the tube.
std::vector<Eigen::Vector3d> bent_tube(double r, double R, double turn_deg, double leg_mm, double noise_mm,
                                       double outlier_fraction, std::uint32_t seed, FilletModel* truth) {
  const double turn = turn_deg * M_PI / 180.0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> axis;  // point, tangent
  const double step = 0.25;
  // leg 1 along +x ending at the origin; arc turning left (towards +y); leg 2
  for (double s = -leg_mm; s < 0; s += step) axis.emplace_back(Eigen::Vector3d(s, 0, 0), Eigen::Vector3d::UnitX());
  const Eigen::Vector3d centre(0, R, 0);
  for (double a = 0; a < turn; a += step / R)
    axis.emplace_back(centre + R * Eigen::Vector3d(std::sin(a), -std::cos(a), 0), Eigen::Vector3d(std::cos(a), std::sin(a), 0));
  const Eigen::Vector3d t2(std::cos(turn), std::sin(turn), 0);
  const Eigen::Vector3d end_arc = centre + R * Eigen::Vector3d(std::sin(turn), -std::cos(turn), 0);
  for (double s = 0; s < leg_mm; s += step) axis.emplace_back(end_arc + s * t2, t2);
  if (truth) {
    const double tl = R * std::tan(0.5 * turn);
    truth->vertex = Eigen::Vector3d(tl, 0, 0);
    truth->leg1 = -Eigen::Vector3d::UnitX();
    truth->leg2 = t2;
    truth->bend_radius_mm = R;
    truth->tube_radius_mm = r;
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const Eigen::Vector3d sensor(0, 0, 600);
  std::vector<Eigen::Vector3d> pts;
  for (const auto& [p, t] : axis) {
    const Eigen::Vector3d n1 = Eigen::Vector3d::UnitZ(), n2 = t.cross(n1).normalized();
    for (int k = 0; k < 24; ++k) {
      const double phi = -0.5 * M_PI + M_PI * (k + 0.5) / 24.0;  // the upper half
      const Eigen::Vector3d q = p + r * (std::cos(phi) * n1 + std::sin(phi) * n2);
      if (uni(rng) < outlier_fraction) {
        pts.push_back(p + 0.6 * r * uni(rng) * (std::cos(phi) * n1 + std::sin(phi) * n2));
        continue;
      }
      const Eigen::Vector3d ray = (q - sensor).normalized();
      pts.push_back(q + noise_mm * gauss(rng) * ray);
    }
  }
  return pts;
}

FilletModel perturbed(const FilletModel& t, double radius_factor) {
  FilletModel m = t;
  m.vertex += Eigen::Vector3d(0.8, -0.6, 0.5);
  m.leg1 = (Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()) * t.leg1).normalized();
  m.leg2 = (Eigen::AngleAxisd(-0.04, Eigen::Vector3d(0.2, 0.1, 1).normalized()) * t.leg2).normalized();
  m.bend_radius_mm = radius_factor * t.bend_radius_mm;
  m.tube_radius_mm = 1.1 * t.tube_radius_mm;
  return m;
}

}  // namespace

TEST(FilletFit, DistanceToTheModel) {
  FilletModel m;
  m.vertex = Eigen::Vector3d::Zero();
  m.leg1 = -Eigen::Vector3d::UnitX();
  m.leg2 = Eigen::Vector3d::UnitY();  // a right-angle turn
  m.bend_radius_mm = 10.0;
  EXPECT_NEAR(m.turn_rad(), 0.5 * M_PI, 1e-12);
  // the arc's centre is (-10, 10); its middle point is at distance 10 from it
  const Eigen::Vector3d centre(-10, 10, 0);
  const Eigen::Vector3d mid = centre + 10.0 * Eigen::Vector3d(1, -1, 0).normalized();
  EXPECT_NEAR(fillet_centreline_distance(m, mid), 0.0, 1e-9);
  EXPECT_NEAR(fillet_centreline_distance(m, mid + Eigen::Vector3d(0, 0, 2)), 2.0, 1e-9);
  EXPECT_NEAR(fillet_centreline_distance(m, centre), 10.0, 1e-9);
  // on the legs, beyond the tangent points (-10, 0) and (0, 10)
  EXPECT_NEAR(fillet_centreline_distance(m, Eigen::Vector3d(-30, 1.5, 0)), 1.5, 1e-9);
  EXPECT_NEAR(fillet_centreline_distance(m, Eigen::Vector3d(-2, 40, 0)), 2.0, 1e-9);
}

// Fits a bent tube (tube radius r, bend radius R, turn in degrees) from a start `radius_factor` x R away.
FilletFit fit_bent_tube(double r, double R, double turn_deg, double leg_mm, std::uint32_t seed, double radius_factor) {
  FilletModel truth;
  const auto pts = bent_tube(r, R, turn_deg, leg_mm, 0.2, 0.1, seed, &truth);
  return fit_fillet(pts, perturbed(truth, radius_factor));
}

// Noise along the sensor's rays spreads the residuals across the surface as sigma x cos(incidence); isotropic noise
// spreads them the same everywhere. ray_noise_scales tells the two apart on the residuals.
TEST(FilletFit, RayNoiseScalesFollowTheIncidence) {
  FilletModel truth;
  const Eigen::Vector3d sensor(0, 0, 600);
  for (const bool along_rays : {true, false}) {
    std::vector<Eigen::Vector3d> pts = bent_tube(3.0, 40.0, 30.0, 20.0, along_rays ? 0.2 : 0.0, 0.0, 7, &truth);
    if (!along_rays) pts = test::add_noise(pts, 0.2 / std::sqrt(3.0), 8);  // 0.2 mm in all
    const std::vector<double> scale = ray_noise_scales(pts, truth, sensor);
    ASSERT_EQ(scale.size(), pts.size());
    std::vector<double> face_on, grazing;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double h = pts[i].z() / 3.0;  // the tube's axis lies in z = 0: the cosine of the incidence, nearly
      if (h > 0.9) face_on.push_back(scale[i]);
      else if (h < 0.4) grazing.push_back(scale[i]);
    }
    const double ratio = median_in_place(face_on) / median_in_place(grazing);
    if (along_rays) {
      EXPECT_GT(ratio, 1.6);  // 1.96; the floor of half the face-on scale allows at most 2
    } else {
      EXPECT_LT(ratio, 1.2);  // 1.00
    }
  }
}

// A short arc of a thin cable (15 deg at 40 mm, 3 mm cable, 0.2 mm noise along the rays, 800 points: about what a
// scan holds there): weighted by the noise across the surface, the fit reads the radius closer to the truth than
// unweighted, and its standard error says so. Over 60 draws the rms error fell 17 % (1.88 -> 1.56 mm; 19 % over 200)
// and the mean standard error 26 % (2.31 -> 1.72 mm).
TEST(FilletFit, WeightsByRayNoiseNarrowTheFit) {
  const Eigen::Vector3d sensor(0, 0, 600);
  FilletFitParams fp;
  fp.max_points = 800;
  double e2_plain = 0, e2_weighted = 0, se_plain = 0, se_weighted = 0;
  const int draws = 60;
  for (int seed = 1; seed <= draws; ++seed) {
    FilletModel truth;
    const auto pts = bent_tube(1.5, 40.0, 15.0, 9.0, 0.2, 0.0, 1000 + seed, &truth);
    FilletModel init = truth;
    init.vertex += Eigen::Vector3d(0.3, -0.2, 0.1);
    init.bend_radius_mm = 1.3 * truth.bend_radius_mm;
    const FilletFit plain = fit_fillet(pts, init, fp);
    ASSERT_TRUE(plain.ok);
    const std::vector<double> scale = ray_noise_scales(pts, plain.model, sensor);
    const FilletFit weighted = fit_fillet(pts, plain.model, fp, &scale);
    ASSERT_TRUE(weighted.ok);
    e2_plain += std::pow(plain.model.bend_radius_mm - 40.0, 2);
    e2_weighted += std::pow(weighted.model.bend_radius_mm - 40.0, 2);
    se_plain += plain.bend_radius_se_mm;
    se_weighted += weighted.bend_radius_se_mm;
  }
  EXPECT_LT(std::sqrt(e2_weighted / e2_plain), 0.92);
  EXPECT_LT(se_weighted, 0.85 * se_plain);
}

// A short tight bend: 17 deg at 2 diameters (an arc of 0.6 diameter). Its centreline leaves the legs' corner by
// only 0.29 mm, yet the surface points give the radius within a few percent.
TEST(FilletFit, ShortTightBendFromNoisySurface) {
  const FilletFit f = fit_bent_tube(6.4, 25.9, 17.0, 40.0, 3, 2.5);
  ASSERT_TRUE(f.ok);
  EXPECT_NEAR(f.model.bend_radius_mm, 25.9, 0.05 * 25.9);
  EXPECT_NEAR(f.model.tube_radius_mm, 6.4, 0.1);
  EXPECT_NEAR(f.model.turn_rad() * 180 / M_PI, 17.0, 0.5);
  EXPECT_LT(f.bend_radius_se_mm, 0.1 * 25.9);
}

TEST(FilletFit, RightAngleBend) {
  const FilletFit f = fit_bent_tube(5.0, 30.0, 90.0, 30.0, 4, 0.6);
  ASSERT_TRUE(f.ok);
  EXPECT_NEAR(f.model.bend_radius_mm, 30.0, 0.02 * 30.0);
  EXPECT_NEAR(f.model.turn_rad() * 180 / M_PI, 90.0, 1.0);
}

TEST(FilletFit, ThinCableLongArc) {
  const FilletFit f = fit_bent_tube(2.5, 60.0, 60.0, 20.0, 5, 1.5);
  ASSERT_TRUE(f.ok);
  EXPECT_NEAR(f.model.bend_radius_mm, 60.0, 0.03 * 60.0);
}

// A very tight bend of a thin cable: 35 deg at R = 1.7 d (d 3.9 mm), densely sampled (the campaign's scans hold a
// tenth of these points, hence their 15-35% standard error).
TEST(FilletFit, VeryTightThinBend) {
  const FilletFit f = fit_bent_tube(1.93, 6.7, 35.0, 15.0, 6, 2.0);
  ASSERT_TRUE(f.ok);
  EXPECT_NEAR(f.model.bend_radius_mm, 6.7, 0.05 * 6.7);
}


// A short tight bend (17 deg at 1.9 d: a 6.4 mm arc on an 11.5 mm cable) between long, looser arcs: the circle
// windows read it as one of the long arcs' looser neighbours; it is found as the most prominent corner of the
// centreline's turn and measured on the surface. (Before corners were ranked by prominence, the long arcs' noisy
// turn plateaus took every corner slot and this bend was read at 66.7 mm, the loosest long arc's figure.)
TEST(FilletRefine, ShortTightBendAmongLongArcs) {
  const double d = 11.5, r = 0.5 * d;
  test::Turtle t;
  t.step = 0.5;
  t.straight(60);
  t.arc(97.0, 65.6, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(31);
  t.arc(21.9, 16.8, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(31);
  t.arc(82.0, 97.9, t.dir.cross(Eigen::Vector3d::UnitZ()));
  t.straight(76);
  t.arc(66.7, 88.9, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(40);
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const std::vector<Eigen::Vector3d> surface = test::tube_surface(t.points, r, 0.15, seed);
    const std::vector<Eigen::Vector3d> centreline = test::add_noise(t.points, 0.08, 100 + seed);
    BendRadiusResult b = measure_bend_radius(centreline, d);
    ASSERT_TRUE(b.min_radius_mm);
    EXPECT_GT(*b.min_radius_mm, 40.0) << "seed " << seed;  // the circle windows alone miss the short bend
    refine_bends_with_fillets(b, centreline, surface, r, d);
    ASSERT_TRUE(b.min_radius_mm);
    EXPECT_NEAR(*b.min_radius_mm, 21.9, 0.12 * 21.9) << "seed " << seed;
  }
}

// A kink too short to measure: 12 deg at R = 15 mm on a 13.2 mm cable, 0.3 mm noise (a 3.1 mm arc; at the apex the
// surface leaves the legs' corner by 0.08 mm, against 0.36 mm at a 66 mm limit). Its radius is not pinned down (held at twice the
// fit's the data fit little worse), but the circle windows' reading is rejected: the bend is reported at the
// loosest radius the surface allows, an upper bound, which a 66 mm (5 d) limit catches. Before, such a fit was
// refused and the circle windows' 140 mm stood (campaign scene_031 missed its cable_C kink when the registration
// moved by 3 um).
TEST(FilletRefine, AShortKinkIsReportedAtAnUpperBound) {
  const double d = 13.2, r = 0.5 * d, truth = 15.0, limit = 5.0 * d;
  test::Turtle t;
  t.step = 0.5;
  t.straight(100);
  t.arc(truth, 12.0, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(100);
  int bounds = 0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    const std::vector<Eigen::Vector3d> surface = test::tube_surface(t.points, r, 0.3, seed);
    const std::vector<Eigen::Vector3d> centreline = test::add_noise(t.points, 0.08, 200 + seed);
    BendRadiusResult b = measure_bend_radius(centreline, d);
    ASSERT_TRUE(b.min_radius_mm);
    EXPECT_GT(*b.min_radius_mm, limit) << "seed " << seed;  // the circle windows alone pass it
    refine_bends_with_fillets(b, centreline, surface, r, d);
    ASSERT_TRUE(b.min_radius_mm);
    EXPECT_LT(*b.min_radius_mm, limit) << "seed " << seed;
    EXPECT_GT(*b.min_radius_mm + 2.0 * b.min_radius_se_mm, truth) << "seed " << seed;
    if (b.min_radius_is_bound) {
      ++bounds;
      EXPECT_GT(*b.min_radius_mm, truth) << "seed " << seed;  // a bound lies above the truth
      // its fit under it: 2.5 standard errors, or less where the free fit lies under the tube's radius
      EXPECT_GE(b.min_radius_fit_mm, 0.8 * r) << "seed " << seed;
      EXPECT_GT(*b.min_radius_mm - b.min_radius_fit_mm, 0.0) << "seed " << seed;
      EXPECT_LE(*b.min_radius_mm - b.min_radius_fit_mm, 2.5 * b.min_radius_se_mm + 1e-9) << "seed " << seed;
    }
  }
  EXPECT_GE(bounds, 3);  // 5 of the 12 noise draws cannot pin the radius (before, all 5 read 130-135 mm)
}

// A kink whose arc another cable half hides (after campaign scene_001's cable_A: a 13.8 deg kink on a 13.7 mm cable,
// limit 34.25 mm, right after 19.3 mm that cable_B hides): here an arc of 8 mm (1.9 mm long) and no surface points over
// the 19.3 mm before it and its first 1.5 mm. What shows of it is a few tenths of a mm, and the fit often draws the corner to a
// point, where the radius no longer changes the fit (its variance unbounded): such a fit was dropped and the cable read
// as the circle windows across the kink do (119 mm in 1 of these 12 noise draws; 2 of 12 with the arc's first 1.5 mm
// and the 20.2 mm before it hidden). It is bounded now, as a kink is.
TEST(FilletRefine, AKinkDrawnToAPointIsBounded) {
  const double d = 13.7, r = 0.5 * d, truth = 8.0, limit = 34.25;
  test::Turtle t;
  t.step = 0.5;
  t.straight(120);
  const double arc_start_x = t.pos.x();
  t.arc(truth, 13.8, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(120);
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    std::vector<Eigen::Vector3d> surface = test::tube_surface(t.points, r, 0.2, seed);
    std::erase_if(surface, [&](const Eigen::Vector3d& x) {
      return x.x() > arc_start_x - 19.3 && x.x() < arc_start_x + 1.5 && std::abs(x.y()) < r + 1.0;
    });
    const std::vector<Eigen::Vector3d> centreline = test::add_noise(t.points, 0.08, 300 + seed);
    BendRadiusResult b = measure_bend_radius(centreline, d);
    refine_bends_with_fillets(b, centreline, surface, r, d);
    ASSERT_TRUE(b.min_radius_mm);
    EXPECT_LT(*b.min_radius_mm, limit) << "seed " << seed;
    EXPECT_GT(*b.min_radius_mm + 2.0 * b.min_radius_se_mm, truth) << "seed " << seed;  // no tighter than the data say
  }
}

// Two bends on a 3.1 mm cable (after campaign scene_044's cable_B): a long looser arc (45 mm over 40 deg) measured
// to +-0.3 mm, and the cable's minimum, a short tight arc (40.1 mm over 15.3 deg, 10.7 mm long: its sagitta 0.36 mm
// against 0.25 mm noise) measured to +-2.5-3.5 mm. The minimum is the bend with the least radius +
// choice_se_factor x se. At a factor of 2 the loose arc won in 8 of 20 noise draws and the reading was within 5 %
// of 40.1 in 6 (within 5 % or 2 se: 12); at 1.5, 12 and 18 (2 -> 6 and 8 -> 12 at 13 deg and 0.2 mm noise).
TEST(FilletRefine, AShortTightArcBeatsALongLooserOne) {
  const double d = 3.1, r = 0.5 * d, truth = 40.1;
  test::Turtle t;
  t.step = 0.5;
  t.straight(156);
  t.arc(45.0, 40.0, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(117);
  t.arc(truth, 15.3, t.dir.cross(Eigen::Vector3d::UnitZ()));
  t.straight(143);
  int within_5_pct = 0, within_2_se = 0;
  double sum_mm = 0.0;
  const int draws = 20;
  for (std::uint32_t seed = 1; seed <= draws; ++seed) {
    const std::vector<Eigen::Vector3d> surface = test::tube_surface(t.points, r, 0.25, seed);
    const std::vector<Eigen::Vector3d> centreline = test::add_noise(t.points, 0.08, 100 + seed);
    BendRadiusResult b = measure_bend_radius(centreline, d);
    refine_bends_with_fillets(b, centreline, surface, r, d);
    ASSERT_TRUE(b.min_radius_mm);
    const double err = std::abs(*b.min_radius_mm - truth);
    within_5_pct += err <= 0.05 * truth;
    within_2_se += err <= 0.05 * truth || err <= 2.0 * b.min_radius_se_mm;
    sum_mm += *b.min_radius_mm;
  }
  EXPECT_GE(within_5_pct, 10);
  EXPECT_GE(within_2_se, 16);
  EXPECT_NEAR(sum_mm / draws, truth, 0.05 * truth);  // the choice does not bias the reading low
}

// A cable lying on a plate (after campaign scene_059's cable_A: 8.1 mm, a 28 deg arc of 41.85 mm), with the mixed
// pixels a structured-light sensor leaves under a silhouette: depths between the cable's flank and the plate, which
// end in the wedge between the tube's unseen underside and the plate, 0.1-0.5 mm outside its surface. Scene_059 had
// 55 among its 1774 window points, most within 6 mm of the apex on one flank, and read 38.72 +- 0.93 mm with a tube
// 0.25 mm too fat. Here 80 such points (this surface is about twice as dense) on the outer or the inner flank pull
// the reading by -2.2 % or +2.4 % on average; with the sensor known, the refit keeps only the side of the tube that
// faces it, and reads within 0.15 %.
TEST(FilletRefine, MixedPixelsUnderACableOnAPlateAreLeftOut) {
  const double d = 8.1, r = 0.5 * d, truth = 41.85;
  test::Turtle t;
  t.step = 0.5;
  t.straight(100);
  t.arc(truth, 28.2, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  const std::size_t apex = t.points.size() - std::size_t(0.5 * truth * 28.2 * M_PI / 180.0 / t.step) - 1;
  t.straight(100);
  const int draws = 4;
  for (const double flank : {1.0, -1.0}) {  // the bend's outer flank, then its inner one
    double sum_with = 0.0, sum_without = 0.0;
    for (std::uint32_t seed = 1; seed <= draws; ++seed) {
      std::vector<Eigen::Vector3d> surface = test::tube_surface(t.points, r, 0.2, seed);
      std::mt19937 rng(500 + seed);
      std::uniform_real_distribution<double> uni(0.0, 1.0);
      for (int k = 0; k < 80; ++k) {
        const std::size_t i = apex - 12 + std::size_t(24 * uni(rng));  // within 6 mm of the apex
        const Eigen::Vector3d tan = (t.points[i + 1] - t.points[i]).normalized();
        const Eigen::Vector3d up = Eigen::Vector3d::UnitZ(), outer = tan.cross(up).normalized();
        const double phi = (120.0 + 20.0 * uni(rng)) * M_PI / 180.0, out = 0.1 + 0.4 * uni(rng);
        surface.push_back(t.points[i] + (r + out) * (std::cos(phi) * up + flank * std::sin(phi) * outer));
      }
      Cloud cloud;
      for (const Eigen::Vector3d& p : surface) cloud.points.push_back(p.cast<float>());
      const KdTree tree(cloud.points);
      const std::vector<Eigen::Vector3d> centreline = test::add_noise(t.points, 0.08, 100 + seed);
      for (const bool sensor : {true, false}) {
        FilletScan scan;
        scan.cloud = &cloud;
        scan.tree = &tree;
        scan.has_sensor = sensor;
        scan.sensor_position = Eigen::Vector3d(0, 0, 600);
        BendRadiusResult b = measure_bend_radius(centreline, d);
        refine_bends_with_fillets(b, centreline, surface, r, d, {}, scan);
        ASSERT_TRUE(b.min_radius_mm);
        (sensor ? sum_with : sum_without) += *b.min_radius_mm;
        if (sensor) {
          EXPECT_NEAR(*b.min_radius_mm, truth, 0.03 * truth) << "flank " << flank << " seed " << seed;
        }
      }
    }
    EXPECT_NEAR(sum_with / draws, truth, 0.0075 * truth) << "flank " << flank;
    // Without the sensor the mixed pixels pull the reading (low on the outer flank, high on the inner one).
    EXPECT_GT(flank * (truth - sum_without / draws), 0.015 * truth) << "flank " << flank;
  }
}

// An arc's end is no bend of its own (after the repeatability scene of seed 12: a 4.8 mm cable's 84.6 deg arc of
// 40.63 mm). A candidate window centred near an arc's end holds only the arc's last stretch: its fillet reads that
// stretch with a few times the whole arc's standard error, and where it reads 1.5-2 of them low it won the choice
// (one scan in 20 read 35.35 +- 2.27 mm for 40.63, where the arc's own fit read 40.64 +- 0.07). Such a fit is a
// bend of its own only where its points inside the arc's window reject the arc's model. Here, at 0.8 mm noise,
// 30 draws: without the rule the reading spreads by 0.25 mm (mean 40.53); with it by 0.13 mm (40.65).
TEST(FilletRefine, AnArcsEndIsNoTighterBend) {
  const double d = 4.8, r = 0.5 * d, truth = 40.63;
  test::Turtle t;
  t.step = 0.5;
  t.straight(40);
  t.arc(truth, 84.6, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(45);
  const int draws = 30;
  for (const bool rule : {true, false}) {
    FilletRefineParams params;
    if (!rule) {
      params.explained_min_log_likelihood_ratio = 0;
      params.cut_arcs_held_elsewhere = false;  // alone, it leaves a spread of 0.15 mm here
    }
    double sum = 0, sum2 = 0;
    for (std::uint32_t seed = 1; seed <= draws; ++seed) {
      const std::vector<Eigen::Vector3d> surface = test::tube_surface(t.points, r, 0.8, seed);
      const std::vector<Eigen::Vector3d> centreline = test::add_noise(t.points, 0.08, 100 + seed);
      BendRadiusResult b = measure_bend_radius(centreline, d);
      refine_bends_with_fillets(b, centreline, surface, r, d, params);
      ASSERT_TRUE(b.min_radius_mm);
      sum += *b.min_radius_mm;
      sum2 += *b.min_radius_mm * *b.min_radius_mm;
    }
    const double mean = sum / draws, sd = std::sqrt(std::max(0.0, sum2 / draws - mean * mean));
    if (rule) {
      EXPECT_NEAR(mean, truth, 0.003 * truth);
      EXPECT_LT(sd, 0.005 * truth);
    } else {
      EXPECT_GT(sd, 0.0055 * truth);  // the arc's ends won the choice (2 of 30 read 2.9 and 3.8 % low)
    }
  }
}

// A bend out of its plane: a helix (radius 30 mm, rising 12 mm per radian: curvature radius 34.8 mm) over 80 deg
// between two straight legs. The planar fillet cannot follow its torsion; with its tilt free the fit is the helix
// tangent to both legs: the curvature radius within 1 %, and the data prefer it by far. At a tilt of nearly zero the
// model is the planar one.
TEST(FilletFit, ATiltedFilletFollowsAHelicalBend) {
  const double r = 30.0, c = 12.0, truth = (r * r + c * c) / r;
  const std::vector<Eigen::Vector3d> axis = test::helical_bend(r, c, 80.0, 25.0, 0.25);
  const Eigen::Vector3d t_in = (axis[20] - axis[0]).normalized();
  const Eigen::Vector3d t_out = (axis.back() - axis[axis.size() - 21]).normalized();
  // The initial vertex: the middle of the legs' common perpendicular.
  const Eigen::Vector3d w0 = axis.front() - axis.back();
  const double b = t_in.dot(t_out), d = t_in.dot(w0), e = t_out.dot(w0);
  const double mu = (b * e - d) / (1.0 - b * b), nu = (e - b * d) / (1.0 - b * b);
  FilletModel init;
  init.vertex = 0.5 * (axis.front() + mu * t_in + axis.back() + nu * t_out);
  init.leg1 = -t_in;
  init.leg2 = t_out;
  init.bend_radius_mm = 1.2 * truth;
  init.tube_radius_mm = 3.3;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const std::vector<Eigen::Vector3d> pts = test::tube_surface(axis, 3.0, 0.2, seed);
    const FilletFit planar = fit_fillet(pts, init);
    ASSERT_TRUE(planar.ok) << "seed " << seed;
    FilletFitParams free_tilt;
    free_tilt.fit_tilt = true;
    const FilletFit tilted = fit_fillet(pts, planar.model, free_tilt);
    ASSERT_TRUE(tilted.ok) << "seed " << seed;
    EXPECT_NEAR(tilted.model.bend_radius_mm, truth, 0.01 * truth) << "seed " << seed << ", planar "
                                                                  << planar.model.bend_radius_mm;
    EXPECT_GT(std::abs(tilted.model.tilt_rad), 0.1) << "seed " << seed;
    EXPECT_NEAR(tilted.model.tube_radius_mm, 3.0, 0.05) << "seed " << seed;
    const double sigma = tilted.sigma_mm, scale = 2.5 * sigma;
    const double ratio =
        2.0 * (fillet_robust_cost(pts, planar.model, scale) - fillet_robust_cost(pts, tilted.model, scale)) /
        (sigma * sigma);
    EXPECT_GT(ratio, 100.0) << "seed " << seed;
    // Continuity: a tilt of 1e-9 is the planar arc.
    FilletModel nearly = planar.model;
    nearly.tilt_rad = 1e-9;
    for (std::size_t i = 0; i < pts.size(); i += 97)
      EXPECT_NEAR(fillet_centreline_distance(nearly, pts[i]), fillet_centreline_distance(planar.model, pts[i]), 1e-6);
  }
}

// A bend whose window reaches into the next one (scene_106 of the 140-scene campaign): a 58 mm arc over 23.5 deg, an
// 11.5 mm straight, then a 124 mm arc turning back the other way. The window around the tight arc (its circle
// window plus two diameters each side) takes 25 mm of the loose arc into its second leg; a fillet with straight legs
// there folds part of that turn into its arc: 16 % low here (9.6 % on the campaign). Cut back to the straight parts of
// its legs, the fit reads the tight arc within 4 % (1.7 % low on average; 0.7 % with the next bend 60 mm away).
TEST(FilletRefine, AWindowReachingIntoTheNextBendIsCutBack) {
  const double d = 12.0, truth = 58.0;
  test::Turtle t;
  t.step = 0.5;
  t.straight(90);
  t.arc(truth, 23.5, t.dir.cross(-Eigen::Vector3d::UnitZ()));
  t.straight(11.5);
  t.arc(124.0, 40.0, t.dir.cross(Eigen::Vector3d::UnitZ()));
  t.straight(60);
  for (const bool rule : {true, false}) {
    FilletRefineParams params;
    if (!rule) params.leg_max_sagitta_mm = 0;
    double worst = 0.0, sum = 0.0;
    const int draws = 4;
    for (std::uint32_t seed = 1; seed <= draws; ++seed) {
      const double radius = test::refined_min_radius(t.points, d, 0.2, seed, 100 + seed, params, 0.03);
      worst = std::max(worst, std::abs(radius - truth));
      sum += radius;
    }
    if (rule)
      EXPECT_LT(worst, 0.04 * truth);
    else
      EXPECT_LT(sum / draws, 0.95 * truth);
  }
}

// The continuation past a fillet's short leg (FilletRefineParams::min_seen_leg_*): an arc of 88 mm whose tangent
// point lies at the origin, its leg along -x (away from the arc, which bends towards +y as it runs along +x). Past
// the tangent point the centreline either goes on along the same circle (the window cut the arc: true), or runs 10 mm
// straight and then bends again, either way, at 107 mm (a short straight between two bends: false). 0.05 mm noise.
TEST(FilletRefine, AnArcGoingOnPastALegIsToldFromTheNextBend) {
  const double R = 88.0, reach = 27.6;
  const Eigen::Vector3d tangent = Eigen::Vector3d::Zero(), leg = -Eigen::Vector3d::UnitX();
  const Eigen::Vector3d other = Eigen::Vector3d(R * std::sin(0.5), R * (1 - std::cos(0.5)), 0);  // 0.5 rad on
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  const auto jitter = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
    return p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  };
  // Samples at arc length s past the tangent point (the arc lengths count down from 100 at the tangent point).
  const auto run = [&](const std::function<Eigen::Vector3d(double)>& at) {
    std::pair<std::vector<Eigen::Vector3d>, std::vector<double>> out;
    for (double s = 0.25; s < reach + 5.0; s += 0.5) {
      out.first.push_back(jitter(at(s)));
      out.second.push_back(100.0 - s);
    }
    return out;
  };
  const auto circle = run([&](double s) { return Eigen::Vector3d(-R * std::sin(s / R), R * (1 - std::cos(s / R)), 0); });
  EXPECT_TRUE(arc_goes_on_past_leg(circle.first, circle.second, 100.0 - reach, 100.0, tangent, leg, other, R));
  for (const double side : {1.0, -1.0}) {
    const auto next_bend = run([&](double s) {
      if (s <= 10.0) return Eigen::Vector3d(-s, 0, 0);
      const double u = s - 10.0, r2 = 107.0;
      return Eigen::Vector3d(-10.0 - r2 * std::sin(u / r2), side * r2 * (1 - std::cos(u / r2)), 0);
    });
    EXPECT_FALSE(arc_goes_on_past_leg(next_bend.first, next_bend.second, 100.0 - reach, 100.0, tangent, leg, other, R))
        << "side " << side;
  }
  // A circle of the same sense but looser than the fit's (a spline's curvature falling off past its peak) is told
  // by which model lies closer: at 1.3 R the circle still, at 3 R the line.
  for (const auto& [factor, goes_on] : {std::pair{1.3, true}, std::pair{3.0, false}}) {
    const double r2 = factor * R;
    const auto looser = run([&](double s) { return Eigen::Vector3d(-r2 * std::sin(s / r2), r2 * (1 - std::cos(s / r2)), 0); });
    EXPECT_EQ(arc_goes_on_past_leg(looser.first, looser.second, 100.0 - reach, 100.0, tangent, leg, other, R), goes_on)
        << "factor " << factor;
  }
}

// A circle figure at a run's end on a fillet's arc is no bend of its own (after campaign scene_136's cable_A, 4.25 mm:
// a helix of radius 31.2 mm rising 27.1 mm per radian, curvature radius 54.8 mm, over 60 deg, where the scan's run ends
// 2 mm past it). The circle windows read the centreline (the chain's joints, one tube radius apart); where no fillet
// can be fitted around a window (at the run's end one leg is missing) its figure stood, and could win the choice
// reading low (51.67 +- 0.61 there, where the arc's fillet read 54.70 +- 0.54). Such a figure is left out where the
// surface points of its window do not prefer its radius to the fillet's. Here, 24 draws with the joints off by 0.15 mm
// per axis: without the rule the circle figure is the minimum in 2, reading 2.1 and 3.8 % low; with it never.
TEST(FilletRefine, ACircleFigureOnAFilletsArcIsNoBendOfItsOwn) {
  const double r = 31.24, c = 27.12, truth = (r * r + c * c) / r, d = 4.25;
  std::vector<Eigen::Vector3d> axis = test::helical_bend(r, c, 60.0, 60.0, 0.25);
  axis.resize(axis.size() - std::size_t(58.0 / 0.25));  // the run ends 2 mm past the helix
  for (const bool rule : {true, false}) {
    FilletRefineParams params;
    if (!rule) params.circle_explained_min_log_likelihood_ratio = 0;
    int circles = 0;
    for (std::uint32_t seed = 1; seed <= 24; ++seed) {
      const std::vector<Eigen::Vector3d> surface = test::tube_surface(axis, 0.5 * d, 0.2, seed);
      std::vector<Eigen::Vector3d> joints;
      for (std::size_t i = 0; i < axis.size(); i += 8) joints.push_back(axis[i]);
      joints.push_back(axis.back());
      const std::vector<Eigen::Vector3d> centreline = test::add_noise(joints, 0.15, 100 + seed);
      BendRadiusResult b = measure_bend_radius(centreline, d);
      refine_bends_with_fillets(b, centreline, surface, 0.5 * d, d, params);
      ASSERT_TRUE(b.min_radius_mm) << "seed " << seed;
      if (std::string(b.min_radius_model) != "circle") continue;
      ++circles;
      EXPECT_LT(*b.min_radius_mm, 0.98 * truth) << "seed " << seed;  // the figures that win read low
    }
    EXPECT_EQ(circles > 0, !rule) << circles << " circle figures";
  }
}

// The rule of FilletRefineParams::cut_arcs_held_elsewhere, on the arcs of campaign scene_069's cable_B (a 3.4 mm cable,
// seen = 1.7 mm): a corner window [174, 242.5] whose fit ended its arc at 242.2, inside the arc [229.2, 249.1] that
// the window [218, 261.4] holds whole, is cut; the whole one is not.
TEST(FilletRefine, AnArcItsWindowCutIsLeftToTheWindowHoldingItWhole) {
  const double seen = 1.7, run = 480.0;
  const FittedArc cut_one{230.0, 242.2, 174.0, 242.5, 1.18}, whole{229.2, 249.1, 218.0, 261.4, 0.48};
  EXPECT_EQ(arcs_cut_by_their_windows({cut_one, whole}, run, seen), (std::vector<std::uint8_t>{1, 0}));
  EXPECT_EQ(arcs_cut_by_their_windows({whole, cut_one}, run, seen), (std::vector<std::uint8_t>{0, 1}));
  // cut at its start instead (the window [240.3, 300] starting 0.5 mm before the arc's start at 240.8)
  EXPECT_EQ(arcs_cut_by_their_windows({{240.8, 255.0, 240.3, 300.0, 1.0}, whole}, run, seen),
            (std::vector<std::uint8_t>{1, 0}));
  // alone, nothing holds the bend whole: kept (the leg test judges it)
  EXPECT_EQ(arcs_cut_by_their_windows({cut_one}, run, seen), (std::vector<std::uint8_t>{0}));
  // the window ends with the run: the arc runs to the cable's end, not into a window's cut
  EXPECT_EQ(arcs_cut_by_their_windows({cut_one, whole}, 242.5, seen), (std::vector<std::uint8_t>{0, 0}));
  // a leg of at least `seen` in the window: not cut
  EXPECT_EQ(arcs_cut_by_their_windows({{230.0, 240.5, 174.0, 242.5, 1.18}, whole}, run, seen),
            (std::vector<std::uint8_t>{0, 0}));
  // the other's window shows too little leg on one side (it is cut itself): it holds nothing whole
  const FittedArc short_leg{229.2, 249.1, 228.0, 261.4, 0.48};
  EXPECT_EQ(arcs_cut_by_their_windows({cut_one, short_leg}, run, seen), (std::vector<std::uint8_t>{0, 0}));
  // the other known less well (a window over the arc's end, its "legs" on the arc): it holds nothing whole
  const FittedArc vague{229.2, 249.1, 218.0, 261.4, 1.5};
  EXPECT_EQ(arcs_cut_by_their_windows({cut_one, vague}, run, seen), (std::vector<std::uint8_t>{0, 0}));
  // the cut end outside the other arc (a bend of its own beside it): not cut
  EXPECT_EQ(arcs_cut_by_their_windows({{200.0, 228.0, 174.0, 228.5, 1.18}, whole}, run, seen),
            (std::vector<std::uint8_t>{0, 0}));
}

// FilletRefineParams::leg_drift_*, on a 9.7 mm tube bending 41.8 deg at 70.97 mm between 40 mm legs (0.25 mm noise
// along the rays, 10 % of the points inside the tube), after H40 scene_029's cable_A, where a crossing cable hid the
// arc's middle: its own model's legs lie along their points (drift 0.01-0.04 mm, z <= 2.4); a fillet that takes the
// arc's first 17 deg for a corner of 43.68 mm has its second leg leave the arc that goes on (2.8 mm, z 37-39); a leg
// 0.5 deg off its points walks 0.33 mm over 40 mm (z 21), under the rule's 0.5 mm, however many points show it.
TEST(FilletRefine, ALegThatPartsFromItsPointsDrifts) {
  const double r = 4.85, R = 70.97;
  const FilletRefineParams params;
  const double kernel = params.fit.kernel_factor * 0.25;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    FilletModel truth;
    const std::vector<Eigen::Vector3d> pts = bent_tube(r, R, 41.8, 40.0, 0.25, 0.1, seed, &truth);
    EXPECT_EQ(fillet_leg_drifts(truth, pts, kernel, params), 0) << "seed " << seed;
    FilletModel corner = truth;  // the same first leg and arc start, turning 17 deg at 43.68 mm
    const double turn = 17.0 * M_PI / 180.0, tight = 43.68;
    corner.bend_radius_mm = tight;
    corner.vertex = Eigen::Vector3d(tight * std::tan(0.5 * turn), 0, 0);
    corner.leg2 = Eigen::Vector3d(std::cos(turn), std::sin(turn), 0);
    EXPECT_EQ(fillet_leg_drifts(corner, pts, kernel, params), 2) << "seed " << seed;  // leg 2
    FilletModel off = truth;  // the second leg turned 0.5 deg about its tangent point
    const Eigen::Vector3d t2 = truth.vertex + R * std::tan(0.5 * truth.turn_rad()) * truth.leg2;
    off.leg2 = Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * truth.leg2;
    off.vertex = t2 - R * std::tan(0.5 * off.turn_rad()) * off.leg2;
    EXPECT_EQ(fillet_leg_drifts(off, pts, kernel, params), 0) << "seed " << seed;
    FilletRefineParams none = params;
    none.leg_drift_max_mm = 0;  // off
    EXPECT_EQ(fillet_leg_drifts(corner, pts, kernel, none), 0);
  }
}

// Noise smoothed over ~1 mm, as a stereo matcher's window smooths its depth errors: Gaussian bumps of width
// `width_mm` centred on a random tenth of the points, scaled to `sigma_mm`, along each point's ray.
std::vector<Eigen::Vector3d> with_smooth_noise(const std::vector<Eigen::Vector3d>& pts, double sigma_mm,
                                               double width_mm, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<std::pair<Eigen::Vector3d, double>> bumps;
  for (const Eigen::Vector3d& p : pts)
    if (uni(rng) < 0.1) bumps.emplace_back(p, gauss(rng));
  std::vector<double> field(pts.size(), 0.0);
  const double reach2 = 16.0 * width_mm * width_mm;
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (const auto& [c, a] : bumps) {
      const double d2 = (pts[i] - c).squaredNorm();
      if (d2 < reach2) field[i] += a * std::exp(-0.5 * d2 / (width_mm * width_mm));
    }
  double ss = 0.0;
  for (double f : field) ss += f * f;
  const double scale = sigma_mm / std::sqrt(ss / double(pts.size()));
  const Eigen::Vector3d sensor(0, 0, 600);
  std::vector<Eigen::Vector3d> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) out[i] = pts[i] + scale * field[i] * (pts[i] - sensor).normalized();
  return out;
}

TEST(FilletFit, ItsStandardErrorCountsNoiseThatNeighboursShare) {
  // A 3 mm tube bent 60 deg at 30 mm, its noise 0.2 mm smoothed by bumps 1 mm wide (correlation exp(-h^2 / 4) at
  // lag h mm): over 30 draws the fitted radius spreads far more than independent noise's standard error says; with
  // the correlation known (FilletFitParams::noise) the standard error matches the spread.
  FilletModel truth;
  const std::vector<Eigen::Vector3d> clean = bent_tube(3.0, 30.0, 60.0, 25.0, 0.0, 0.0, 1, &truth);
  NoiseCorrelation nc;
  nc.bin_mm = 0.5;
  for (int k = 0; k < 10; ++k) {
    const double h = (k + 0.5) * nc.bin_mm;
    nc.rho.push_back(std::exp(-0.25 * h * h));
  }
  nc.inflation = 40.0;
  FilletFitParams counted;
  counted.noise = &nc;
  std::vector<double> radii;
  double se_independent = 0.0, se_counted = 0.0;
  const int draws = 30;
  for (int d = 0; d < draws; ++d) {
    const std::vector<Eigen::Vector3d> pts = with_smooth_noise(clean, 0.2, 1.0, 100 + d);
    const FilletFit independent = fit_fillet(pts, perturbed(truth, 1.2));
    const FilletFit f = fit_fillet(pts, perturbed(truth, 1.2), counted);
    ASSERT_TRUE(f.ok);
    EXPECT_NEAR(f.model.bend_radius_mm, independent.model.bend_radius_mm, 1e-9);  // the same fit
    EXPECT_GT(f.noise_inflation, 2.0);
    radii.push_back(f.model.bend_radius_mm);
    se_independent += independent.bend_radius_se_mm / draws;
    se_counted += f.bend_radius_se_mm / draws;
  }
  double mean = 0.0, var = 0.0;
  for (double r : radii) mean += r / draws;
  for (double r : radii) var += (r - mean) * (r - mean) / (draws - 1);
  const double spread = std::sqrt(var);
  EXPECT_GT(spread, 2.0 * se_independent);
  EXPECT_GT(se_counted, 0.6 * spread);
  EXPECT_LT(se_counted, 1.7 * spread);
}
