"""Scenes of the fresh campaigns (bench/RESULTS.md: `ewis simulate --seed 5151 --campaign 60`, evaluated only after
the code was frozen) on which a change once went wrong, made again one by one through the CLI: a campaign's scene
i is `ewis simulate --seed <its truth.json "seed"> --defect <kind of scene i>` (src/sim/campaign.cpp), byte for
byte the same files. Each is inspected as `ewis evaluate` does (with its pose.txt) and compared with its truth."""
import json
import math
import os
import shutil
import subprocess
import sys
import unittest

from ewis_cli import EWIS, run, tmpdir, validate


def inspect_scene(d, scene, pose=True):
    """Inspects the simulated scene folder `scene` (inside the scratch folder d, removed after) as `ewis evaluate`
    does; returns its truth.json, its schema-checked report.json and the inspection's stderr."""
    out = os.path.join(d, "out")
    initial = ["--pose", os.path.join(scene, "pose.txt")] if pose else []
    inspection = run("inspect", "--cad", os.path.join(scene, "scene.obj"), "--plan", os.path.join(scene, "plan.json"),
                     "--scan", os.path.join(scene, "scan.ply"), *initial, "--out", out, "--quiet", check=0)
    with open(os.path.join(scene, "truth.json")) as f:
        truth = json.load(f)
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    validate(report, "report.schema.json")
    shutil.rmtree(d, ignore_errors=True)
    return truth, report, inspection.stderr


def simulate_and_inspect(name, seed, *defect, pose=True):
    d = tmpdir(name)
    scene = os.path.join(d, "scene")
    run("simulate", "--out", scene, "--seed", seed, *defect, "--quiet", check=0)
    truth, report, _ = inspect_scene(d, scene, pose)
    return truth, report


def element(report, name):
    return next(e for e in report["elements"] if e["name"] == name)


def truth_and_report_cable(truth, report, name):
    return next(c for c in truth["cables"] if c["name"] == name), element(report, name)


class FreshScenes(unittest.TestCase):
    def assert_no_foreign_object_and_a_pass(self, truth, report):
        self.assertEqual(truth["defects"], [])
        for e in report["elements"]:
            self.assertEqual([i for i in e.get("interferences", []) if i["with"] is None], [], e["name"])
        self.assertEqual(report["verdict"], "pass")

    def assert_bend_within_5_percent(self, measured, truth_cable):
        truth_mm = truth_cable["min_bend_radius_mm"]
        self.assertAlmostEqual(measured["min_bend_radius_mm"], truth_mm, delta=0.05 * truth_mm)

    def test_no_tube_is_traced_in_the_mixed_points_behind_a_cable(self):
        # Seed 5151's scene_037. A 6.4 mm cable ~35 mm over a structure: the mixed pixels under it form sheets along
        # the rays. A later run of its trace (the cable's own points taken) fitted a tube between them 8 mm behind
        # the cable and followed it for 60 mm: the cable read 472 mm long for 461 and a 28.7 mm bend for 77.9. The
        # points such a tube hides do not excuse it (TubeParams::hidden_check asks that the tube be in front).
        truth, report = simulate_and_inspect("fresh037", 6328988860928790600, "--defect", "clearance",
                                             "--clearance-with", "bracket")
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertTrue(a["found"])
        self.assertLessEqual(a["length_mm"], 1.02 * t["length_mm"])
        self.assert_bend_within_5_percent(a, t)
        self.assertTrue(a["bend_ok"])

    def test_a_cable_moved_onto_its_neighbours_place_is_traced_on_its_own_points(self):
        # Seed 9999's scene_057 (J60). cable_A moved 10-15 mm off its CAD toward bracket_1 by a clearance defect,
        # cable_C lying along A's CAD: A's first trace took C, the untangling split C's points between the two, A was
        # never traced on its own and its 0.08 mm gap to the bracket was missed (the verdict "fail" only through a
        # false A-C contact). Conflicting runs are judged before the untangling, the owner by the plan's diameters.
        truth, report = simulate_and_inspect("fresh_j057", 5331431243244478551, "--defect", "clearance",
                                             "--clearance-with", "bracket")
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertTrue(a["found"])
        # 488.8 of 558.9 mm (clamps and connectors hide the rest); before, 350.8 (its runs on C's leftovers)
        self.assertGreaterEqual(a["length_mm"], 0.8 * t["length_mm"])
        self.assertLessEqual(a["length_mm"], 1.02 * t["length_mm"])
        gap = next(d["gap_mm"] for d in truth["defects"] if d["element"] == "cable_A")
        near = [i for i in a["interferences"] if i["with"] == "bracket_1"]
        self.assertEqual(len(near), 1)
        self.assertAlmostEqual(near[0]["min_distance_mm"], gap, delta=0.5)
        self.assertFalse([i for i in a["interferences"] if i["with"] == "cable_C"])
        self.assert_bend_within_5_percent(a, t)

    def test_an_arc_its_window_cut_gives_way_to_the_window_holding_it_whole(self):
        # Seed 2026's scene_069 (the README's campaign). cable_B (3.4 mm): a corner window 36 mm before its 40 deg arc
        # ended 7 mm into it and read 24.34 +- 1.18 for 28.75 (FilletRefineParams::cut_arcs_held_elsewhere).
        truth, report = simulate_and_inspect("fresh_c069", 16600345389652871043, "--defect", "clearance",
                                             "--clearance-with", "cable")
        t, b = truth_and_report_cable(truth, report, "cable_B")
        self.assert_bend_within_5_percent(b, t)

    def test_a_kink_whose_fit_is_drawn_to_a_point_is_bounded(self):
        # Seed 2026's scene_001 (the README's campaign). cable_A (13.7 mm) has a 13.8 deg kink of 21.45 mm (limit
        # 34.25) right after 19.3 mm that cable_B hides; its fillet drew the corner to a point (the radius's variance
        # unbounded), was dropped, and the cable read 67.55 mm at its next bend: a missed defect. Now an upper bound.
        truth, report = simulate_and_inspect("fresh_c001", 1637080640729033865, "--defect", "bend")
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertTrue(a["min_bend_radius_is_bound"])
        self.assertLess(a["min_bend_radius_mm"], t["allowed_bend_radius_mm"])
        self.assertGreater(a["min_bend_radius_mm"], t["min_bend_radius_mm"])  # a bound lies above the truth
        self.assertFalse(a["bend_ok"])
        self.assertEqual(report["verdict"], "fail")

    def test_a_kink_bounded_over_its_limit_whose_fit_lies_under_it_fails(self):
        # R40 (`--seed 3579 --campaign 40 --pose-error-deg 8 --pose-error-mm 40 --noise-mm 0.25 --outliers 0.5`)
        # scene_001: cable_A's kink (10.64 mm, limit 18.6) is too short for its radius to be measured. It read at most
        # 22.95 +- 7.35 mm, its fit at 4.57, and passed: a missed defect. An upper bound over the limit passes only
        # when the fit + 1 standard error reaches the limit too (InspectParams::bound_verdict_se).
        truth, report = simulate_and_inspect("fresh_r001", 13940546468693284340, "--defect", "bend", "--pose-error-deg",
                                             "8", "--pose-error-mm", "40", "--noise-mm", "0.25", "--outliers", "0.5")
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertTrue(a["min_bend_radius_is_bound"])
        self.assertGreater(a["min_bend_radius_mm"], t["allowed_bend_radius_mm"])
        self.assertLess(a["min_bend_radius_fit_mm"] + a["min_bend_radius_se_mm"], t["allowed_bend_radius_mm"])
        self.assertFalse(a["bend_ok"])
        self.assertEqual(report["verdict"], "fail")

    def test_a_circle_figure_whose_fillet_cut_the_arc_gives_way_to_the_arcs_fillets(self):
        # Seed 6061's scene_019 (B40: `--defect bend --cables 3 --pose-error-deg 5 --pose-error-mm 15`). cable_B
        # (5.5 mm): an arc of 56.16 mm over 80 deg in the middle of its run. The candidate in its middle had its fillet
        # refused (the arc goes on past the window) and its circle figure, 53.07 +- 1.15, won over the two fillets
        # that read the arc 56.25 +- 0.25 and 56.16 +- 0.48 (FilletRefineParams::circle_explained_cut).
        truth, report = simulate_and_inspect("fresh_b019", 13722413221345252063, "--defect", "bend", "--cables", "3",
                                             "--pose-error-deg", "5", "--pose-error-mm", "15")
        t, b = truth_and_report_cable(truth, report, "cable_B")
        self.assert_bend_within_5_percent(b, t)

    def test_a_fillets_leg_that_parts_from_its_points_at_a_runs_end_is_cut_back(self):
        # Scene_021 of the fresh set H40 (`ewis simulate --seed 24680 --campaign 40 --cables 3 --mismatch-patches 200
        # --noise-mm 0.3 --outliers 0.4 --pose-error-deg 6 --pose-error-mm 20`). cable_A, a 23.3 mm hose, has a bend
        # defect: a 15.7 deg kink of 67.50 mm (limit 104.85) 57.5 mm after a 33.8 deg arc of 205.6 mm. The fillet of the
        # window at its run's end read 44.70 +- 7.56 (-34 %): its 103 mm leg ran to the run's end over the arc before,
        # its axis walking 0.64 mm off its points (z 19). Refitted over half that leg it reads 64.92 +- 3.42
        # (FilletRefineParams::leg_drift_*). Since the scene's bracket is wound outward (scene/orient_faces.hpp) its
        # registration differs by 0.02 mm at the cables: the leg drifts 0.49 mm (z 15), the window stood at 48.28 +-
        # 6.87 under the 0.5 mm floor of the time (2.8 standard errors from the truth), and refitted it reads 63.17 +-
        # 3.89: within 2 standard errors, not 5 %.
        truth, report = simulate_and_inspect("fresh_h021", 18322320647454247596, "--defect", "bend", "--cables", "3",
                                             "--mismatch-patches", "200", "--noise-mm", "0.3", "--outliers", "0.4",
                                             "--pose-error-deg", "6", "--pose-error-mm", "20")
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertLess(abs(a["min_bend_radius_mm"] - t["min_bend_radius_mm"]), 2.0 * a["min_bend_radius_se_mm"])
        self.assertFalse(a["bend_ok"])
        self.assertEqual(report["verdict"], "fail")

    def test_a_cable_no_start_was_found_for_beside_its_neighbour_is_traced(self):
        # The spline bundles of bench/spline_scenes.py (`--seed 34 --bundle`, scene_009; the script needs numpy): two
        # 9.2 mm cables 0.09 mm apart, their CAD 4.5 mm apart. Every start sphere on cable_A's CAD held cable_B's
        # surface too and no tube fitted there: cable_A was not found at all (the verdict "fail" for that, the contact
        # unseen). A cable no start was found for is now traced again without the other cables' runs' points
        # (InspectParams::retrace_unfound).
        try:
            import numpy  # noqa: F401
        except ImportError:
            self.skipTest("numpy is missing (bench/spline_scenes.py needs it; scripts/setup.sh installs python3-numpy)")
        d = tmpdir("fresh_sb009")
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../bench/spline_scenes.py")
        subprocess.run([sys.executable, script, "--ewis", EWIS, "--out", d, "--scenes", "1", "--first", "9", "--seed",
                        "34", "--bundle"], check=True, capture_output=True, timeout=600)
        truth, report, _ = inspect_scene(d, os.path.join(d, "scene_009"))
        self.assertEqual([(x["kind"], x["element"], x["with"]) for x in truth["defects"]],
                         [("clearance", "cable_A", "cable_B")])
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertTrue(a["found"])
        self.assertGreater(a["length_mm"], 0.85 * t["length_mm"])
        gaps = [i["min_distance_mm"] for i in a["interferences"] if i["with"] == "cable_B"]
        self.assertTrue(gaps)
        self.assertAlmostEqual(min(gaps), truth["defects"][0]["gap_mm"], delta=0.1)
        self.assertEqual(report["verdict"], "fail")

    def test_noise_neighbouring_points_share_raises_no_bend_alarm(self):
        # The second scanner (bench/second_scanner.py; needs numpy) with depth noise smoothed over a Gaussian of 2
        # pixels, as a stereo matcher's window smooths it (0.2 mm, with 0.08 mm independent, dropouts and holes):
        # campaign seed 2718's scene_006. Counted as independent, the noise made bumps into bends: cable_A (59.92 mm)
        # read 18.13 and cable_C (70.18 mm) 13.01 +- 1.38, a false alarm. The scan's noise correlation is measured
        # (report.json scan.noise_inflation, 20-25 on this set) and the bend fits count it (FilletFitParams::noise).
        try:
            import numpy  # noqa: F401
        except ImportError:
            self.skipTest("numpy is missing (bench/second_scanner.py needs it; scripts/setup.sh installs python3-numpy)")
        d = tmpdir("fresh_z006")
        campaign, rescanned = os.path.join(d, "campaign"), os.path.join(d, "rescanned")
        run("simulate", "--out", campaign, "--seed", "2718", "--campaign", "7", "--quiet", check=0)
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../bench/second_scanner.py")
        subprocess.run([sys.executable, script, "--ewis", EWIS, "--campaign", campaign, "--seed", "2718", "--out",
                        rescanned, "--first", "6", "--last", "6", "--sigma-mm", "0.08", "--ray-sigma-mm", "0.2",
                        "--ray-corr-px", "2", "--dropout", "0.7", "--holes", "0.05", "--outliers", "0.4", "--mixed",
                        "0.5"], check=True, capture_output=True, timeout=600)
        truth, report, _ = inspect_scene(d, os.path.join(rescanned, "scene_006"))
        self.assertGreater(report["scan"]["noise_inflation"], 10.0)
        self.assert_no_foreign_object_and_a_pass(truth, report)
        for name in ("cable_A", "cable_C"):
            t, c = truth_and_report_cable(truth, report, name)
            self.assertLess(abs(c["min_bend_radius_mm"] - t["min_bend_radius_mm"]) / t["min_bend_radius_mm"], 0.1,
                            name)

    def test_a_smooth_tubes_peak_at_a_runs_end_is_no_bend(self):
        # Seed 7777's scene_052 (H60). A 10.9 mm cable's run starts where it leaves its connector, on a helix: the
        # smooth tube over the run's first 28 mm read a peak of 27.48 +- 0.39 mm 7 mm from the run's start, for a
        # cable whose tightest bend is 41.05 mm (FilletRefineParams::smooth_min_end_diameters).
        truth, report = simulate_and_inspect("fresh_h052", 12579878884279486141)
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assert_bend_within_5_percent(a, t)

    def test_a_box_resting_on_a_bend_does_not_bend_the_smooth_tube(self):
        # Seed 8888's scene_035 (I60, 0.3 mm noise). A 13 x 14 x 8 mm box rests 0.57 mm above cable_B (15.8 mm) in the
        # middle of its 106.27 mm, 45 deg bend: the quartic tube bent to the box's noisy surface and read 92.24 +- 0.62
        # (the fillet 105.24 +- 0.35), its whole advantage in the box's stretch (FilletRefineParams::smooth_spread_bins).
        truth, report = simulate_and_inspect("fresh_i035", 5363269809087452800, "--defect", "foreign_object",
                                             "--noise-mm", "0.3")
        t, b = truth_and_report_cable(truth, report, "cable_B")
        self.assert_bend_within_5_percent(b, t)
        self.assertTrue([i for i in b["interferences"] if i["with"] is None])  # the box: a foreign object

    def test_a_sphere_whose_near_flank_is_unseen_is_found(self):
        # Seed 4040's scene_015 (made with --mismatch-patches 300; the same miss without them). A 13.4 mm sphere lies
        # 3.3 mm beside cable_A (clearance 6 mm), seen from above: its nearest seen point is 7.0 mm from the cable and
        # nothing hides the cable, but the rays through its seen points, continued behind them, pass within the
        # clearance (InterferenceParams::shadow_within_clearance). Before: no entry, the scene passed.
        truth, report = simulate_and_inspect("fresh_m015", 13826068474363721469, "--defect", "foreign_object")
        sphere = truth["foreign_objects"][0]["shapes"][0]
        centre = [sphere["frame"][i][3] for i in range(3)]
        a = element(report, "cable_A")
        found = [i for i in a["interferences"] if i["with"] is None]
        self.assertEqual(len(found), 1)
        self.assertLess(sum((x - c) ** 2 for x, c in zip(found[0]["closest_on_other"], centre)) ** 0.5,
                        sphere["radius_mm"] + 2.0)
        self.assertEqual(report["verdict"], "fail")

    def test_stereo_mismatch_patches_are_no_foreign_objects(self):
        # Seed 4040's scene_020, a clean scene scanned with 300 mismatch patches (2-6 px at one wrong depth, 1-10 mm
        # off: docs/sim.md): 8 clumps of 14-36 points beside or over the cables were foreign objects, the verdict
        # "fail". Each stands alone in space: the object it belongs to is under 16 mm^2
        # (InterferenceParams::min_object_area_mm2).
        truth, report = simulate_and_inspect("fresh_m020", 6747542969816516530, "--mismatch-patches", "300")
        self.assertEqual(truth["scan"]["mismatch_patches"], 300)
        self.assertGreater(truth["scan"]["mismatched"], 3000)
        self.assert_no_foreign_object_and_a_pass(truth, report)

    def test_a_mismatch_patch_on_a_thin_cable_does_not_bend_the_smooth_tube(self):
        # Seed 4040's scene_004 with 300 mismatch patches, inspected without its pose: a patch of 6 x 6 px (32 points)
        # sits 1.4 mm deep in the 3.7 mm cable_B, across its whole seen width. The quartic tube bent to it and read
        # 18.51 mm for a 49.74 mm bend (with the pose, 17.42 before FilletRefineParams::smooth_spread_top_bins): a
        # false bend alarm. The patch stands off the tube by a step and is left out of the bend fits
        # (surface_clumps.hpp).
        truth, report = simulate_and_inspect("fresh_m004", 12497757700967302806, "--mismatch-patches", "300",
                                             pose=False)
        t, b = truth_and_report_cable(truth, report, "cable_B")
        self.assert_bend_within_5_percent(b, t)
        self.assertEqual(report["verdict"], "pass")

    def test_a_mismatch_patch_at_a_runs_end_is_no_hairpin(self):
        # Seed 4040's scene_038 with 300 mismatch patches, inspected without its pose: a 4 x 4 px patch 1.44 mm in
        # front of the 4.5 mm cable_A ends its trace from both sides, and a fillet at a run's end fitted a 162 deg
        # hairpin of 2.78 +- 0.07 mm where the centreline turns 24 deg (a false alarm; the cable's tightest bend is
        # 44.23 mm, allowed 20.25). A fit turning more than the centreline by over max(60 deg, its turn) is refused
        # (FilletRefineParams::max_turn_excess_deg). The cable's bend then reads 41.66 mm, as with the pose (-5.8 %,
        # one of the noise-limited readings in bench/RESULTS.md).
        truth, report = simulate_and_inspect("fresh_m038", 2827067339720150427, "--mismatch-patches", "300",
                                             pose=False)
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertGreater(a["min_bend_radius_mm"], 0.85 * t["min_bend_radius_mm"])
        self.assertTrue(a["bend_ok"])
        self.assertEqual(report["verdict"], "pass")

    # Seed 2468's campaign (`ewis simulate --seed 2468 --campaign 40 --cables 3 --mismatch-patches 150 --outliers 0.45
    # --noise-mm 0.25`, bench/RESULTS.md, session 30): three scenes it got wrong.
    Y40 = ("--cables", "3", "--mismatch-patches", "150", "--outliers", "0.45", "--noise-mm", "0.25")

    def test_two_crossing_wires_a_few_points_across_are_traced_whole(self):
        # WA20 (`ewis simulate --seed 4344 --campaign 20 --cable-diameter-mm 1.5 3`, the forty-third session) scene_010:
        # two 1.7 mm wires, 3-4 points across at 0.5 mm. No seed's free fit read the wire's radius (0.54-1.37 mm for
        # 0.85), cable_A was "not found" and the clean scene failed. With the plan's radius held (InspectParams::
        # thin_cable_max_px) A was traced, but up the mixed pixels between it and cable_B crossing 16 mm above
        # (along the rays), and the two read 0.34 mm apart; a thin tube's step along the rays now ends it.
        truth, report = simulate_and_inspect("wires_a010", 16320270365966069462, "--defect", "none",
                                             "--cable-diameter-mm", "1.5", "3")
        self.assertEqual(truth["defects"], [])
        for name in ("cable_A", "cable_B"):
            t, c = truth_and_report_cable(truth, report, name)
            self.assertTrue(c["found"], name)
            self.assertGreaterEqual(c["cad_traced_fraction"], 0.9, name)
            self.assertLessEqual(c["length_mm"], 1.02 * t["length_mm"], name)
            self.assertEqual(c["interferences"], [], name)
        self.assertEqual(report["verdict"], "pass")

    def test_a_box_on_a_wire_beside_its_clamp_is_found(self):
        # WA20 scene_015: a 15 x 10 x 9 mm box lies on a 2.8 mm wire 20 mm from the wire's clamp. The clamp ends the
        # runs and the box hides the wire: 42.6 mm untraced, over the 40 mm the interference bridges, and the box was
        # not looked for. The stretch inside the clamp (an attached element) no longer counts against the bridge.
        truth, report = simulate_and_inspect("wires_a015", 8793831929583423397, "--defect", "foreign_object",
                                             "--cable-diameter-mm", "1.5", "3")
        self.assertEqual([d["kind"] for d in truth["defects"]], ["foreign_object"])
        a = element(report, "cable_A")
        self.assertTrue([i for i in a["interferences"] if i["with"] is None])
        self.assertEqual(report["verdict"], "fail")

    def test_a_dropped_run_on_a_neighbour_leaves_the_cables_place_to_be_traced(self):
        # Scene_027. cable_A (4.4 mm), displaced up to 9 mm from its CAD, touches bracket_1. Its second run took 416 mm
        # of cable_C (5.9 mm, 1.33x: dropped by max_seed_radius_ratio) and covered A's CAD samples along C: A's 204 mm
        # beside them were never traced and the contact was missed (verdict "pass"). A dropped run's CAD samples now
        # stay to seed the next run.
        truth, report = simulate_and_inspect("fresh_y027", 5052510371093637836, "--defect", "clearance",
                                             "--clearance-with", "bracket", *self.Y40)
        self.assertEqual([(d["kind"], d["with"]) for d in truth["defects"]], [("clearance", "bracket_1")])
        t, a = truth_and_report_cable(truth, report, "cable_A")
        self.assertGreater(a["length_mm"], 0.85 * t["length_mm"])
        self.assertIn("bracket_1", [i["with"] for i in a["interferences"]])
        self.assertEqual(report["verdict"], "fail")

    def test_stacks_of_mixed_pixels_make_no_object_of_a_patch(self):
        # Scene_034, clean. A mismatch patch and 10 stacks of mixed pixels beside clamp_1, 1.1 mm over cable_C (9 mm):
        # 290 points on 34 pixels reached the object's cap of 196 points and read as a foreign object. Its pixels decide.
        truth, report = simulate_and_inspect("fresh_y034", 811363054781086098, *self.Y40)
        self.assert_no_foreign_object_and_a_pass(truth, report)

    def test_a_patch_at_a_runs_end_does_not_grow_over_the_cables_own_end(self):
        # Scene_024, clean. 20 points of a patch 1.7 mm over cable_A (13.6 mm, clearance 1 mm) hide it from the sensor
        # next to where its run ends before connector_J2; grown over the cable's own untraced last 6 mm (176 points on
        # its surface, past the run's end) they read as an object.
        truth, report = simulate_and_inspect("fresh_y024", 7930135820276914539, *self.Y40)
        self.assert_no_foreign_object_and_a_pass(truth, report)

    def test_a_pose_slid_along_the_plate_beyond_the_fine_passs_reach_is_found_again(self):
        # R40 (`--seed 3579 --campaign 40 --pose-error-deg 8 --pose-error-mm 40 --noise-mm 0.25 --outliers 0.5`) scene_022,
        # clean: one cable on a plate with three small blocks. The coarse pass left the pose 10 mm along the plate and
        # the fine pass stayed 8.95 mm off (fitness 0.972, trusted): two false foreign objects. The fitness probed
        # along the weakest direction of translation brings it back (weak_direction.hpp).
        truth, report = simulate_and_inspect("fresh_r022", 13763930464431052023, "--defect", "none", "--pose-error-deg",
                                             "8", "--pose-error-mm", "40", "--noise-mm", "0.25", "--outliers", "0.5")
        angle_deg, shift_mm = pose_difference(report["registration"]["transform"], truth["camera_to_cad"])
        self.assertLess(angle_deg, 0.1)
        self.assertLess(shift_mm, 0.5)
        self.assert_no_foreign_object_and_a_pass(truth, report)


def pose_difference(transform, truth_transform):
    """The rotation angle (deg) and the translation (mm) of transform^-1 * truth_transform."""
    a = [row[:3] for row in transform[:3]]
    b = [row[:3] for row in truth_transform[:3]]
    trace = sum(a[k][i] * b[k][i] for i in range(3) for k in range(3))  # trace(A^T B)
    angle_deg = math.degrees(math.acos(max(-1.0, min(1.0, (trace - 1.0) / 2.0))))
    shift_mm = math.dist([row[3] for row in transform[:3]], [row[3] for row in truth_transform[:3]])
    return angle_deg, shift_mm


class PlannedViews(unittest.TestCase):
    """Scans from `ewis plan`'s covering views (bench/planned_views.py --seed 1357 --scenes 20), made again one by
    one: the campaign's scene as `ewis simulate --scene-only` of its scene_truth.json seed, its view's camera_to_cad
    as the plan wrote it, the scan seeded as the script seeds it."""

    def scan_from_view(self, name, scene_seed, defect, camera_to_cad, scan_seed):
        d = tmpdir(name)
        scene = os.path.join(d, "scene")
        scan = os.path.join(d, "scan")
        run("simulate", "--scene-only", "--seed", scene_seed, "--defect", defect, "--cables", "3", "--out", scene,
            "--quiet", check=0)
        view = os.path.join(d, "view.json")
        with open(view, "w") as f:
            json.dump({"best": [{"rank": 1, "camera_to_cad": camera_to_cad}]}, f)
        run("simulate", "--cad", os.path.join(scene, "scene.obj"), "--plan", os.path.join(scene, "plan.json"),
            "--viewpoints", view, "--rank", "1", "--seed", scan_seed, "--noise-mm", "0.2", "--outliers", "0.4",
            "--out", scan, "--quiet", check=0)
        return inspect_scene(d, scan)

    def test_cables_filling_a_side_view_are_not_registered_onto_the_plate(self):
        # Scene_010, view 2 (the sensor level with the plate, looking along it): the cables fill most of the view,
        # the plate is a strip, brackets and connectors are small. From pose.txt (30 mm / 5 deg off) the cables lay
        # outside the coarse pass's 20 mm zones and were matched onto the plate: 16.6 deg and 129 mm off (fitness
        # 0.57, 32 % of the CAD in front of the scan), three cables "not found". An untrusted local result is
        # refined again with the zones grown by the whole expected error (ScanToCadParams::local_retry_grown_full).
        side = [[-1.0, 0.0, 0.0, 80.532299034], [0.0, -0.258819045, -0.965925826, 576.237257786],
                [0.0, -0.965925826, 0.258819045, -73.092607863], [0.0, 0.0, 0.0, 1.0]]
        truth, report, stderr = self.scan_from_view("view_010_2", 17713814334625751485, "none", side, 1357102)
        angle_deg, shift_mm = pose_difference(report["registration"]["transform"], truth["camera_to_cad"])
        self.assertLess(angle_deg, 0.1)
        self.assertLess(shift_mm, 1.0)
        self.assertGreater(report["registration"]["fitness"], 0.85)
        self.assertEqual(report["verdict"], "pass")
        self.assertNotIn("registration is doubtful", stderr)

    def test_a_pose_the_scan_does_not_support_is_warned_about(self):
        # Scene_011, view 2 (a bend defect; the same kind of side view). Neither pose.txt's refinements nor the global
        # search found the pose (14.1 deg and 110 mm off; from the true pose ICP stays there at a fitness of 0.96): the
        # pose it kept had a fitness of 0.54 with 27 % of the CAD's faces toward the sensor in front of what was
        # measured, and the inspection said so (InspectParams::doubtful_fitness). Since the near retry
        # (ScanToCadParams::local_retry_near_mm) the planned-view set's scan of it registers within 0.01 deg.
        side = [[-1.0, 0.0, 0.0, -21.224548909], [0.0, -0.258819045, -0.965925826, 570.913128696],
                [0.0, -0.965925826, 0.258819045, -70.511315656], [0.0, 0.0, 0.0, 1.0]]
        truth, report, stderr = self.scan_from_view("view_011_2", 9974125156251401964, "bend", side, 1357112)
        angle_deg, _ = pose_difference(report["registration"]["transform"], truth["camera_to_cad"])
        if angle_deg > 1.0:
            self.assertIn("registration is doubtful", stderr)
        else:  # found after all: then it must not be doubted
            self.assertNotIn("registration is doubtful", stderr)


if __name__ == "__main__":
    unittest.main()
