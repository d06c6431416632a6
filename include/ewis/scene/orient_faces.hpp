#pragma once
// Face winding of a CAD scene made consistent and outward.
//
// Everything that asks which way a CAD face looks (the registration's culling of faces turned away from the sensor,
// the free-space check, the samples' normals) takes a triangle's winding as its outward side (counter-clockwise seen
// from outside). Exporters do not all agree: a mesh wound clockwise, or a solid written inside out, turned every face
// of the demo scene away from the sensor, and the registration put the scan 1.36 m away upside down (fitness 0.85,
// no warning). So the winding is repaired once at load:
//   1. Per element, vertices are welded by position (exporters split them at hard edges and by normal), and across
//      every edge two triangles share (not across edges of three or more: non-manifold) the second is wound as the
//      first; each connected set of triangles is a component.
//   2. A closed component (every edge shared by exactly two of its triangles) is turned outward by the sign of its
//      enclosed volume. An open one (a sheet, a pipe without caps, a box missing a face) has no inside the mesh can
//      tell: it is wound as most of its area was given, and made two-sided (each of its triangles again, wound the
//      other way, after the element's own), so that whichever side the sensor sees faces it. A panel modelled as one
//      sheet wound away from the sensor put the demo's registration 1.35 m off, upside down.
#include <cstddef>
#include <vector>

#include "ewis/scene/scene.hpp"

namespace ewis {

struct OrientationRepair {
  std::size_t flipped_triangles = 0;   // triangles whose winding was reversed
  std::size_t elements_changed = 0;    // elements with at least one of them
  std::size_t components = 0;          // connected components over all elements
  std::size_t open_components = 0;     // of which open (their outside is not known)
  std::size_t two_sided_triangles = 0; // their triangles, added again wound the other way
};

// Reverses the winding of the triangles that need it and adds the other side of open components (vertices are not
// moved or merged; element ranges and statistics are updated), in the elements `which` selects (empty: all).
// `inspect` repairs the elements its plan does not call cables (inspect/pipeline.hpp `orient_rigid_faces`), the
// `register` command every element of a mesh; `load_scene` leaves the file's winding as it is.
OrientationRepair orient_faces_outward(Scene& scene, const std::vector<bool>& which = {});

}  // namespace ewis
