#pragma once
// Distances to a measured cable's fitted model: the chain of sub-cable axes (paper 4.2.3-4.2.4).
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "ewis/core/cylinder.hpp"

namespace ewis {

struct ChainPoint {
  double distance_mm = 0.0;        // to the nearest axis segment
  std::size_t segment = 0;         // which one
  double t = 0.0;                  // where on it, 0..1
  bool beyond_end = false;         // p lies past a run's end (a run: segments joined end to start)
};

// Nearest point of the chain's axis polyline to p. An empty chain gives infinite distance.
ChainPoint distance_to_chain(const std::vector<Cylinder>& chain, const Eigen::Vector3d& p);

// The chain plus a bridge over each short break between two runs: run ends of different runs that face each
// other (each within 60 deg of the line to the other), each the other's nearest, at most max_break_mm apart,
// joined by a cubic Hermite curve that leaves each end along its run (as short cylinders, a run of its own). A
// cable traced in runs on both sides of something lying over it (a clamp, a crossing cable, a foreign object)
// is still there under it: what lies in the break is judged against the bridge, not dropped as "beyond the
// cable's end", and the cable's own untraced surface there stays within its surface band.
// `held_mm` (optional): the length of a segment that lies where something holds the cable by design (its clamps and
// connectors, which end its runs); a break is measured without it.
std::vector<Cylinder> bridge_short_breaks(
    const std::vector<Cylinder>& chain, double max_break_mm,
    const std::function<double(const Eigen::Vector3d&, const Eigen::Vector3d&)>& held_mm = {});

// Least distance between segments [p0, p1] and [q0, q1]; the closest points in `on_p`, `on_q` when given.
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                        const Eigen::Vector3d& q1, Eigen::Vector3d* on_p = nullptr, Eigen::Vector3d* on_q = nullptr);

// Least distance between two chains' axes (the surface gap is this minus both radii).
double chain_distance(const std::vector<Cylinder>& a, const std::vector<Cylinder>& b, Eigen::Vector3d* on_a = nullptr,
                      Eigen::Vector3d* on_b = nullptr);

}  // namespace ewis
