// Consistent, outward face winding (see orient_faces.hpp).
#include "ewis/scene/orient_faces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "ewis/core/parallel.hpp"
#include "ewis/core/scratch.hpp"

namespace ewis {
namespace {

// A position's bits, -0 as +0 (so that welding by value and by bits agree).
std::array<std::uint32_t, 3> position_key(const Eigen::Vector3f& p) {
  std::array<std::uint32_t, 3> k{};
  for (int i = 0; i < 3; ++i) {
    const float v = p[i] + 0.0f;
    std::memcpy(&k[std::size_t(i)], &v, sizeof v);
  }
  return k;
}

// Lexicographic order of three words (std::array's operator< calls memcmp: a fifth of the time).
bool less3(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b) {
  return a[0] != b[0] ? a[0] < b[0] : a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
}
bool same3(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

struct EdgeUse {
  std::uint32_t lo, hi;  // welded vertices
  std::uint32_t triangle;
  bool forward;  // wound lo -> hi
};

// Whether every edge of the triangles `members` (their welded corners; `flip` the winding each is turned to) is used
// by exactly two of them, wound opposite ways along it: a closed, consistently wound surface on its own, whatever
// other triangles of the element share its edges.
bool closed_by_own_edges(const std::vector<std::uint32_t>& welded, const std::vector<std::uint32_t>& members,
                         const std::vector<std::uint8_t>& flip) {
  std::vector<EdgeUse> edges;
  edges.reserve(3 * members.size());
  for (std::uint32_t t : members)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t u = welded[3 * std::size_t(t) + std::size_t(k)], v = welded[3 * std::size_t(t) + std::size_t((k + 1) % 3)];
      if (u == v) continue;
      if (flip[t]) std::swap(u, v);
      edges.push_back({std::min(u, v), std::max(u, v), t, u < v});
    }
  std::sort(edges.begin(), edges.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.triangle < b.triangle;
  });
  for (std::size_t i = 0; i < edges.size(); i += 2) {
    if (i + 1 >= edges.size()) return false;
    const EdgeUse &a = edges[i], &b = edges[i + 1];
    if (a.lo != b.lo || a.hi != b.hi || a.forward == b.forward) return false;
    if (i + 2 < edges.size() && edges[i + 2].lo == a.lo && edges[i + 2].hi == a.hi) return false;
  }
  return true;
}

struct ElementRepair {
  std::size_t flipped = 0, components = 0, open = 0;
  std::vector<std::uint32_t> open_triangles;  // of open components (element-local indices)
};

// The element's triangles [first, first + count): which to reverse.
ElementRepair orient_element(Scene& scene, std::size_t first, std::size_t count) {
  ElementRepair out;
  if (count == 0) return out;
  // 1. Weld the corners by position: the vertices the element uses (by index first: most files share them), then
  // those of one position.
  std::vector<std::uint32_t> corner_vertex(3 * count);  // per corner its vertex index
  for (std::size_t c = 0; c < 3 * count; ++c)
    corner_vertex[c] = static_cast<std::uint32_t>(scene.triangles[first + c / 3][int(c % 3)]);
  const auto [lo_it, hi_it] = std::minmax_element(corner_vertex.begin(), corner_vertex.end());
  const std::uint32_t lo_vertex = *lo_it;
  const std::size_t span = std::size_t(*hi_it - lo_vertex) + 1;
  // The vertices used, ascending, and each corner's slot among them: by a table over the index range where the
  // element's vertices lie together (as every reader stores them), else by sorting.
  std::vector<std::uint32_t> used, slot_of_corner(3 * count);
  if (span <= 4 * corner_vertex.size() + 1024) {
    std::vector<std::uint32_t> slot(span, 0);
    for (std::uint32_t v : corner_vertex) slot[v - lo_vertex] = 1;
    for (std::size_t i = 0; i < span; ++i)
      if (slot[i]) {
        slot[i] = static_cast<std::uint32_t>(used.size());
        used.push_back(lo_vertex + static_cast<std::uint32_t>(i));
      }
    for (std::size_t c = 0; c < corner_vertex.size(); ++c) slot_of_corner[c] = slot[corner_vertex[c] - lo_vertex];
  } else {
    used = corner_vertex;
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    for (std::size_t c = 0; c < corner_vertex.size(); ++c)
      slot_of_corner[c] = static_cast<std::uint32_t>(std::lower_bound(used.begin(), used.end(), corner_vertex[c]) -
                                                     used.begin());
  }
  release_memory(corner_vertex);
  struct Keyed {
    std::array<std::uint32_t, 3> key;
    std::uint32_t slot;  // index into `used`
  };
  std::vector<Keyed> keyed(used.size());
  for (std::size_t i = 0; i < used.size(); ++i)
    keyed[i] = {position_key(scene.vertices[used[i]]), static_cast<std::uint32_t>(i)};
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return !same3(a.key, b.key) ? less3(a.key, b.key) : a.slot < b.slot;
  });
  std::vector<std::uint32_t> weld_of_slot(used.size());
  std::uint32_t vertex_count = 0;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i > 0 && !same3(keyed[i].key, keyed[i - 1].key)) ++vertex_count;
    weld_of_slot[keyed[i].slot] = vertex_count;
  }
  ++vertex_count;
  release_memory(keyed);
  std::vector<std::uint32_t> welded(3 * count);
  for (std::size_t c = 0; c < 3 * count; ++c) welded[c] = weld_of_slot[slot_of_corner[c]];
  release_memory(slot_of_corner);
  release_memory(used);
  release_memory(weld_of_slot);

  // 2. Edges, bucketed by their lower vertex (then by the other and the triangle): two triangles sharing one (and no
  // third) are wound alike across it.
  std::vector<std::uint32_t> bucket(std::size_t(vertex_count) + 1, 0);
  for (std::size_t t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = welded[3 * t + std::size_t(k)], v = welded[3 * t + std::size_t((k + 1) % 3)];
      if (u != v) ++bucket[std::min(u, v) + 1];
    }
  for (std::size_t i = 0; i < vertex_count; ++i) bucket[i + 1] += bucket[i];
  std::vector<EdgeUse> edges(bucket[vertex_count]);
  {
    std::vector<std::uint32_t> fill(bucket.begin(), bucket.end() - 1);
    for (std::size_t t = 0; t < count; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = welded[3 * t + std::size_t(k)], v = welded[3 * t + std::size_t((k + 1) % 3)];
        if (u != v) edges[fill[std::min(u, v)]++] = {std::min(u, v), std::max(u, v), static_cast<std::uint32_t>(t), u < v};
      }
  }
  for (std::size_t i = 0; i < vertex_count; ++i)  // (each bucket a vertex's few edges)
    std::sort(edges.begin() + std::ptrdiff_t(bucket[i]), edges.begin() + std::ptrdiff_t(bucket[i + 1]),
              [](const EdgeUse& a, const EdgeUse& b) { return a.hi != b.hi ? a.hi < b.hi : a.triangle < b.triangle; });
  release_memory(bucket);
  struct Link {
    std::uint32_t other;
    bool same;  // both wound the same way along the edge: one of the two must turn
  };
  std::vector<std::uint32_t> degree(count + 1, 0);
  std::vector<std::uint8_t> on_border(count, 0);  // has an edge not shared by exactly two triangles
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // index pairs into `edges`
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    if (j - i == 2 && edges[i].triangle != edges[i + 1].triangle) {
      pairs.emplace_back(i, i + 1);
      ++degree[edges[i].triangle + 1];
      ++degree[edges[i + 1].triangle + 1];
    } else {
      for (std::size_t k = i; k < j; ++k) on_border[edges[k].triangle] = 1;
    }
    i = j;
  }
  for (std::size_t t = 0; t < count; ++t) degree[t + 1] += degree[t];
  std::vector<Link> links(degree[count]);
  {
    std::vector<std::uint32_t> fill(degree.begin(), degree.end() - 1);
    for (const auto& [a, b] : pairs) {
      const EdgeUse& ea = edges[a];
      const EdgeUse& eb = edges[b];
      const bool same = ea.forward == eb.forward;
      links[fill[ea.triangle]++] = {eb.triangle, same};
      links[fill[eb.triangle]++] = {ea.triangle, same};
    }
  }
  release_memory(edges);
  release_memory(pairs);

  // Triangles whose reverse is there too (a surface written two-sided): such a pair is an open component's both sides
  // already. Found when the first open component asks (a closed mesh never does).
  std::vector<std::uint8_t> has_twin;
  const auto find_twins = [&] {
    has_twin.assign(count, 0);
    struct Corners {
      std::array<std::uint32_t, 3> key;  // welded corners, ascending
      bool odd;                          // wound as an odd permutation of them
      std::uint32_t triangle;
    };
    std::vector<Corners> corners(count);
    for (std::size_t t = 0; t < count; ++t) {
      std::array<std::uint32_t, 3> k = {welded[3 * t], welded[3 * t + 1], welded[3 * t + 2]};
      bool odd = false;
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2 - i; ++j)
          if (k[std::size_t(j)] > k[std::size_t(j + 1)]) {
            std::swap(k[std::size_t(j)], k[std::size_t(j + 1)]);
            odd = !odd;
          }
      corners[t] = {k, odd, static_cast<std::uint32_t>(t)};
    }
    std::sort(corners.begin(), corners.end(), [](const Corners& a, const Corners& b) {
      return !same3(a.key, b.key) ? less3(a.key, b.key) : a.triangle < b.triangle;
    });
    for (std::size_t i = 0; i < corners.size();) {
      std::size_t j = i + 1;
      while (j < corners.size() && same3(corners[j].key, corners[i].key)) ++j;
      bool even_seen = false, odd_seen = false;
      for (std::size_t k = i; k < j; ++k) (corners[k].odd ? odd_seen : even_seen) = true;
      if (even_seen && odd_seen)
        for (std::size_t k = i; k < j; ++k) has_twin[corners[k].triangle] = 1;
      i = j;
    }
  };

  // Components, each wound as its first triangle (breadth first, in index order: deterministic).
  constexpr std::uint8_t kUnset = 2;
  std::vector<std::uint8_t> flip(count, kUnset);
  std::vector<std::uint32_t> queue;
  std::vector<std::uint32_t> members;
  for (std::size_t start = 0; start < count; ++start) {
    if (flip[start] != kUnset) continue;
    members.clear();
    queue.assign(1, static_cast<std::uint32_t>(start));
    flip[start] = 0;
    bool closed = true;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      members.push_back(t);
      if (on_border[t]) closed = false;
      for (std::uint32_t l = degree[t]; l < degree[t + 1]; ++l) {
        const Link& link = links[l];
        if (flip[link.other] != kUnset) continue;  // (a non-orientable strip keeps its first winding)
        flip[link.other] = static_cast<std::uint8_t>(flip[t] ^ (link.same ? 1 : 0));
        queue.push_back(link.other);
      }
    }
    ++out.components;
    // 3. Outward: a closed component by the sign of its volume (about its first vertex, for precision), an open
    // one as most of its area was given.
    const Eigen::Vector3d origin = scene.vertices[std::size_t(scene.triangles[first + members[0]][0])].cast<double>();
    double volume6 = 0.0, area_turned = 0.0, area_kept = 0.0;
    for (std::uint32_t t : members) {
      const Eigen::Vector3i& tri = scene.triangles[first + t];
      const Eigen::Vector3d a = scene.vertices[std::size_t(tri[0])].cast<double>() - origin;
      Eigen::Vector3d b = scene.vertices[std::size_t(tri[1])].cast<double>() - origin;
      Eigen::Vector3d c = scene.vertices[std::size_t(tri[2])].cast<double>() - origin;
      const double area = (b - a).cross(c - a).norm();
      if (flip[t]) {
        std::swap(b, c);
        area_turned += area;
      } else {
        area_kept += area;
      }
      volume6 += a.dot(b.cross(c));
    }
    // A solid that touches another along an edge or a face of the same element (a plate and the wall standing on it,
    // written with shared corners) has edges of three or more triangles there, which link nothing, yet each of its own
    // edges is used by two of its own triangles, wound opposite ways: closed all the same. Taken as open, it was made
    // two-sided: a 6 mm plate's underside, turned up, held a registration started 5 mm low 6 mm under the plate.
    // (A surface written two-sided also closes so, but encloses nothing: its volume is no more than rounding.)
    const bool closed_alone = !closed && closed_by_own_edges(welded, members, flip) &&
                              std::abs(volume6) > 1e-6 * std::pow(area_turned + area_kept, 1.5);
    bool invert;
    if ((closed && volume6 != 0.0) || closed_alone) {
      invert = volume6 < 0.0;
    } else {
      ++out.open;
      invert = area_turned > area_kept;
      // (its other side added, unless every triangle of it has its reverse already)
      if (has_twin.empty()) find_twins();
      const bool two_sided = std::all_of(members.begin(), members.end(), [&](std::uint32_t t) { return has_twin[t] != 0; });
      if (!two_sided) out.open_triangles.insert(out.open_triangles.end(), members.begin(), members.end());
    }
    if (invert)
      for (std::uint32_t t : members) flip[t] ^= 1;
  }
  for (std::size_t t = 0; t < count; ++t)
    if (flip[t]) {
      Eigen::Vector3i& tri = scene.triangles[first + t];
      std::swap(tri[1], tri[2]);
      ++out.flipped;
    }
  return out;
}

}  // namespace

OrientationRepair orient_faces_outward(Scene& scene, const std::vector<bool>& which) {
  std::vector<ElementRepair> per(scene.elements.size());
  parallel_for_each_index(
      scene.elements.size(),
      [&](std::size_t e) {
        if (which.empty() || (e < which.size() && which[e]))
          per[e] = orient_element(scene, scene.elements[e].first_triangle, scene.elements[e].triangle_count);
      },
      1);
  OrientationRepair out;
  for (std::size_t e = 0; e < per.size(); ++e) {
    scene.elements[e].reoriented_triangles = static_cast<std::uint32_t>(per[e].flipped);
    out.flipped_triangles += per[e].flipped;
    out.elements_changed += per[e].flipped > 0 ? 1 : 0;
    out.components += per[e].components;
    out.open_components += per[e].open;
    out.two_sided_triangles += per[e].open_triangles.size();
  }
  // Open components get their other side: each triangle again, wound the other way, after the element's own.
  if (out.two_sided_triangles > 0) {
    std::vector<Eigen::Vector3i> triangles;
    std::vector<std::uint32_t> triangle_element;
    triangles.reserve(scene.triangles.size() + out.two_sided_triangles);
    triangle_element.reserve(triangles.capacity());
    for (std::size_t e = 0; e < per.size(); ++e) {
      Element& el = scene.elements[e];
      const std::size_t first = el.first_triangle;
      el.first_triangle = static_cast<std::uint32_t>(triangles.size());
      triangles.insert(triangles.end(), scene.triangles.begin() + std::ptrdiff_t(first),
                       scene.triangles.begin() + std::ptrdiff_t(first + el.triangle_count));
      std::vector<std::uint32_t> open = per[e].open_triangles;
      std::sort(open.begin(), open.end());
      for (std::uint32_t t : open) {
        const Eigen::Vector3i& tri = scene.triangles[first + t];
        triangles.emplace_back(tri[0], tri[2], tri[1]);
      }
      el.triangle_count += static_cast<std::uint32_t>(open.size());
      triangle_element.insert(triangle_element.end(), el.triangle_count, static_cast<std::uint32_t>(e));
    }
    scene.triangles = std::move(triangles);
    scene.triangle_element = std::move(triangle_element);
    update_element_stats(scene);
  }
  return out;
}

}  // namespace ewis
