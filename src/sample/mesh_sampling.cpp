// Area-weighted random sampling of CAD triangles (paper 4.1.1).
#include "ewis/sample/mesh_sampling.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/core/scratch.hpp"

namespace ewis {
namespace {

// splitmix64: a tiny, well-mixed generator whose output is the same on every platform and library
// (std::uniform_real_distribution is not specified bit for bit).
struct SplitMix64 {
  static constexpr std::uint64_t kIncrement = 0x9E3779B97F4A7C15ull;  // the state's step per draw
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += kIncrement);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  // The generator as it stands `draws` draws later (the state only adds a constant per draw).
  SplitMix64 skipped(std::uint64_t draws) const { return {state + draws * kIncrement}; }
};

std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
  SplitMix64 g{a ^ (b * 0xD1B54A32D192ED03ull)};
  g.next();
  return g.next();
}

constexpr std::size_t kBlock = 4096;  // samples per RNG stream: fixes the streams independently of threads

struct ElementPlan {
  int element = 0;
  std::size_t count = 0;
  std::size_t offset = 0;           // first output index
  std::vector<double> cumulative;   // cumulative triangle areas of the element
};

std::vector<std::size_t> counts_for(const std::vector<double>& areas, double spacing) {
  std::vector<std::size_t> c(areas.size());
  for (std::size_t i = 0; i < areas.size(); ++i) {
    const double n = std::round(areas[i] / (spacing * spacing));
    c[i] = areas[i] > 0 ? std::max<std::size_t>(1, static_cast<std::size_t>(std::min(n, 1e15))) : 0;
  }
  return c;
}

}  // namespace

MeshSamples sample_mesh(const Scene& scene, const MeshSamplingParams& params) {
  if (!(params.spacing_mm > 0) || !std::isfinite(params.spacing_mm))
    throw InputError("", "mesh sampling spacing must be a positive number (mm)");
  std::vector<int> selected = params.elements;
  if (selected.empty())
    for (std::size_t e = 0; e < scene.elements.size(); ++e) selected.push_back(static_cast<int>(e));
  for (int e : selected)
    if (e < 0 || std::size_t(e) >= scene.elements.size())
      throw InputError("", "mesh sampling: element index " + std::to_string(e) + " out of range");

  std::vector<double> areas(selected.size());
  for (std::size_t i = 0; i < selected.size(); ++i) areas[i] = scene.elements[selected[i]].area_mm2;

  // paper 4.1.1: the number of points per element follows its area (count = area / spacing^2).
  double spacing = params.spacing_mm;
  std::vector<std::size_t> counts = counts_for(areas, spacing);
  auto total_of = [](const std::vector<std::size_t>& c) {
    std::size_t t = 0;
    for (std::size_t x : c) t += x;
    return t;
  };
  if (params.max_points > 0) {
    // Raise the spacing until the cap holds (bounded: each step grows the spacing by at least 1%).
    for (int it = 0; it < 200 && total_of(counts) > params.max_points; ++it) {
      spacing *= std::max(1.01, std::sqrt(double(total_of(counts)) / double(params.max_points)));
      counts = counts_for(areas, spacing);
    }
    // Still over only when there are more non-empty elements than max_points: keep the first ones.
    std::size_t budget = params.max_points;
    for (std::size_t& c : counts) {
      c = std::min(c, budget);
      budget -= c;
    }
  }

  std::vector<ElementPlan> plans;
  std::size_t total = 0;
  for (std::size_t i = 0; i < selected.size(); ++i) {
    if (counts[i] == 0) continue;
    ElementPlan p;
    p.element = selected[i];
    p.count = counts[i];
    p.offset = total;
    total += p.count;
    const Element& e = scene.elements[p.element];
    p.cumulative.resize(e.triangle_count);
    double acc = 0;
    for (std::uint32_t t = 0; t < e.triangle_count; ++t) {
      const Eigen::Vector3i& tri = scene.triangles[e.first_triangle + t];
      const Eigen::Vector3d a = scene.vertices[tri[0]].cast<double>();
      acc += 0.5 * (scene.vertices[tri[1]].cast<double>() - a).cross(scene.vertices[tri[2]].cast<double>() - a).norm();
      p.cumulative[t] = acc;
    }
    if (!(acc > 0)) {
      total -= p.count;
      continue;
    }
    plans.push_back(std::move(p));
  }

  // Work items: (plan, block of kBlock samples), each with its own RNG stream seeded from
  // (seed, element, block), so results do not depend on the thread count or scheduling.
  struct Item {
    std::size_t plan, begin, end, block;
  };
  std::vector<Item> items;
  for (std::size_t p = 0; p < plans.size(); ++p)
    for (std::size_t b = 0, s = 0; s < plans[p].count; ++b, s += kBlock)
      items.push_back({p, s, std::min(plans[p].count, s + kBlock), b});

  // Sample s of item k, handed to `emit(point, normal, element, triangle)`. Each sample takes kDrawsPerSample draws
  // of its item's stream, so sample s is drawn alone from the stream's start skipped by that many per sample before
  // it: the same sample as in a pass over the whole item.
  constexpr std::uint64_t kDrawsPerSample = 3;  // the triangle, then the point in it (two)
  auto stream_of = [&](std::size_t k) {
    const Item& it = items[k];
    return SplitMix64{mix(mix(params.seed, static_cast<std::uint64_t>(plans[it.plan].element)), it.block)};
  };
  auto draw_sample = [&](std::size_t k, SplitMix64& rng, std::size_t s, const auto& emit) {
    const ElementPlan& p = plans[items[k].plan];
    const Element& e = scene.elements[p.element];
    // Triangle with probability proportional to its area: binary search in the cumulative areas.
    const double pick = rng.uniform() * p.cumulative.back();
    std::size_t t = std::upper_bound(p.cumulative.begin(), p.cumulative.end(), pick) - p.cumulative.begin();
    t = std::min(t, p.cumulative.size() - 1);
    const std::uint32_t tri_index = e.first_triangle + static_cast<std::uint32_t>(t);
    const Eigen::Vector3i& tri = scene.triangles[tri_index];
    const Eigen::Vector3d a = scene.vertices[tri[0]].cast<double>();
    const Eigen::Vector3d b = scene.vertices[tri[1]].cast<double>();
    const Eigen::Vector3d c = scene.vertices[tri[2]].cast<double>();
    // Uniform point in the triangle (Osada et al.): r1 = sqrt(u1) makes the density uniform.
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    const Eigen::Vector3d q = (1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c;
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    emit(s, q.cast<float>(), n.cast<float>(), static_cast<std::uint32_t>(p.element), tri_index);
  };
  auto draw_item = [&](std::size_t k, const auto& emit) {
    SplitMix64 rng = stream_of(k);
    for (std::size_t s = items[k].begin; s < items[k].end; ++s) draw_sample(k, rng, s, emit);
  };

  MeshSamples out;
  if (params.keep) {
    // Which samples `keep` accepts, per block (their offsets within it), then only those drawn again into their
    // place (blocks in their order = the order of the full result). Memory: the kept samples and 4 bytes each.
    std::vector<std::vector<std::uint32_t>> kept_in(items.size());
    parallel_for_each_index(items.size(), [&](std::size_t k) {
      std::vector<std::uint32_t>& in = kept_in[k];
      draw_item(k, [&](std::size_t s, const Eigen::Vector3f& q, const Eigen::Vector3f& nrm, std::uint32_t,
                       std::uint32_t) {
        if (params.keep(q, nrm)) in.push_back(static_cast<std::uint32_t>(s - items[k].begin));
      });
    }, 1);
    std::vector<std::size_t> offset(items.size() + 1, 0);
    for (std::size_t k = 0; k < items.size(); ++k) offset[k + 1] = offset[k] + kept_in[k].size();
    const std::size_t kept = offset.back();
    out.cloud.points.resize(kept);
    out.cloud.normals.resize(kept);
    out.element.resize(kept);
    out.triangle.resize(kept);
    parallel_for_each_index(items.size(), [&](std::size_t k) {
      std::size_t o = offset[k];
      const SplitMix64 start = stream_of(k);
      for (const std::uint32_t j : kept_in[k]) {
        SplitMix64 rng = start.skipped(kDrawsPerSample * j);
        draw_sample(k, rng, items[k].begin + j, [&](std::size_t, const Eigen::Vector3f& q, const Eigen::Vector3f& nrm,
                                                   std::uint32_t element, std::uint32_t triangle) {
          out.cloud.points[o] = q;
          out.cloud.normals[o] = nrm;
          out.element[o] = element;
          out.triangle[o] = triangle;
          ++o;
        });
      }
    }, 1);
    return out;
  }

  // Large outputs are filled by the threads below: huge pages for their first touch (core/scratch.hpp).
  out.cloud.points.resize(total);
  prefer_huge_pages(out.cloud.points.data(), total * sizeof(Eigen::Vector3f));
  out.cloud.normals.resize(total);
  prefer_huge_pages(out.cloud.normals.data(), total * sizeof(Eigen::Vector3f));
  for (std::vector<std::uint32_t>* v : {&out.element, &out.triangle}) {
    v->reserve(total);
    prefer_huge_pages(v->data(), total * sizeof(std::uint32_t));
    v->resize(total);
  }
  parallel_for_each_index(items.size(), [&](std::size_t k) {
    const std::size_t offset = plans[items[k].plan].offset;
    draw_item(k, [&](std::size_t s, const Eigen::Vector3f& q, const Eigen::Vector3f& n, std::uint32_t element,
                     std::uint32_t triangle) {
      const std::size_t o = offset + s;
      out.cloud.points[o] = q;
      out.cloud.normals[o] = n;
      out.element[o] = element;
      out.triangle[o] = triangle;
    });
  }, 1);
  return out;
}

}  // namespace ewis
