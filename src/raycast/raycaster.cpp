// Raycaster: one Embree device and scene per instance; single rays, packets and parallel batches.
#include "ewis/raycast/raycaster.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "camera_block.hpp"
#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"

namespace ewis {

namespace {

const char* error_name(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "none";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw ProcessingError(std::string("Embree: ") + what + ": " + error_name(e));
}

// Unit direction, or false for a zero / non-finite direction (such a ray hits nothing).
bool unit_direction(const Ray& ray, Eigen::Vector3f& dir) {
  const float n = ray.direction.norm();
  if (!(n > 0.f) || !std::isfinite(n) || !ray.origin.allFinite()) return false;
  dir = ray.direction / n;
  return true;
}

}  // namespace

struct Raycaster::Impl {
  const Scene* scene = nullptr;
  RTCDevice device = nullptr;
  RTCScene rtc_scene = nullptr;
  std::vector<std::uint32_t> prim_to_triangle;  // Embree primID -> scene triangle
  std::vector<bool> include;                    // per element
  int packet_width = 1;

  ~Impl() {
    if (rtc_scene) rtcReleaseScene(rtc_scene);
    if (device) rtcReleaseDevice(device);
  }

  Hit make_hit(float tfar, unsigned prim, float ngx, float ngy, float ngz, const Eigen::Vector3f& dir) const {
    Hit h;
    if (prim >= prim_to_triangle.size()) return h;
    h.distance_mm = tfar;
    h.triangle = prim_to_triangle[prim];
    h.element = scene->triangle_element[h.triangle];
    Eigen::Vector3f n(ngx, ngy, ngz);
    const float len = n.norm();
    n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(-dir);
    if (n.dot(dir) > 0) n = -n;  // face the ray
    h.normal = n;
    return h;
  }

  template <class RayHitN, int N, class IntersectFn>
  void packet(IntersectFn intersect, const Ray* rays, int count, Hit* hits, RTCIntersectContextFlags flags) const {
    alignas(64) int valid[N];
    alignas(64) RayHitN rh;
    Eigen::Vector3f dirs[N];
    for (int i = 0; i < N; ++i) {
      valid[i] = 0;
      rh.ray.org_x[i] = rh.ray.org_y[i] = rh.ray.org_z[i] = 0.f;
      rh.ray.dir_x[i] = rh.ray.dir_y[i] = 0.f;
      rh.ray.dir_z[i] = 1.f;
      rh.ray.tnear[i] = 0.f;
      rh.ray.tfar[i] = -1.f;
      rh.ray.time[i] = 0.f;
      rh.ray.mask[i] = 0xFFFFFFFFu;
      rh.ray.id[i] = static_cast<unsigned>(i);
      rh.ray.flags[i] = 0;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
      if (i >= count) continue;
      hits[i] = Hit{};
      if (!unit_direction(rays[i], dirs[i])) continue;
      valid[i] = -1;
      rh.ray.org_x[i] = rays[i].origin.x();
      rh.ray.org_y[i] = rays[i].origin.y();
      rh.ray.org_z[i] = rays[i].origin.z();
      rh.ray.dir_x[i] = dirs[i].x();
      rh.ray.dir_y[i] = dirs[i].y();
      rh.ray.dir_z[i] = dirs[i].z();
      rh.ray.tfar[i] = rays[i].tmax_mm;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = flags;
    intersect(valid, rtc_scene, &context, &rh);
    for (int i = 0; i < count; ++i)
      if (valid[i] && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID)
        hits[i] = make_hit(rh.ray.tfar[i], rh.hit.primID[i], rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i], dirs[i]);
  }

  Hit single(const Ray& ray) const {
    Eigen::Vector3f dir;
    if (!unit_direction(ray, dir)) return Hit{};
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x();
    rh.ray.org_y = ray.origin.y();
    rh.ray.org_z = ray.origin.z();
    rh.ray.dir_x = dir.x();
    rh.ray.dir_y = dir.y();
    rh.ray.dir_z = dir.z();
    rh.ray.tnear = 0.f;
    rh.ray.tfar = ray.tmax_mm;
    rh.ray.time = 0.f;
    rh.ray.mask = 0xFFFFFFFFu;  // Debian's Embree has ray masks on: 0 would hit nothing
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(rtc_scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit{};
    return make_hit(rh.ray.tfar, rh.hit.primID, rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z, dir);
  }

  void cast_packet(const Ray* rays, int count, Hit* hits, RTCIntersectContextFlags flags) const {
    if (count <= 0) return;
    if (packet_width == 1) {
      for (int i = 0; i < count; ++i) hits[i] = single(rays[i]);
      return;
    }
    // Split into packets of the device's width.
    for (int begin = 0; begin < count; begin += packet_width) {
      const int n = std::min(packet_width, count - begin);
      switch (packet_width) {
        case 16: packet<RTCRayHit16, 16>(rtcIntersect16, rays + begin, n, hits + begin, flags); break;
        case 8: packet<RTCRayHit8, 8>(rtcIntersect8, rays + begin, n, hits + begin, flags); break;
        default: packet<RTCRayHit4, 4>(rtcIntersect4, rays + begin, n, hits + begin, flags); break;
      }
    }
  }

  // Lanes [lane0, lane0 + N) of a camera block as one packet.
  template <class RayHitN, int N, class IntersectFn>
  void camera_packet(IntersectFn intersect, const detail::CameraBlock& b, int lane0, detail::CameraHits& out,
                     bool want_normals) const {
    alignas(64) int valid[N];
    alignas(64) RayHitN rh;
    // Whole-array fills and copies (vectorised); lanes past `count` are switched off by `valid`.
    for (int i = 0; i < N; ++i) valid[i] = lane0 + i < b.count ? -1 : 0;
    std::fill_n(rh.ray.org_x, N, b.origin.x());
    std::fill_n(rh.ray.org_y, N, b.origin.y());
    std::fill_n(rh.ray.org_z, N, b.origin.z());
    std::memcpy(rh.ray.dir_x, b.dx + lane0, N * sizeof(float));
    std::memcpy(rh.ray.dir_y, b.dy + lane0, N * sizeof(float));
    std::memcpy(rh.ray.dir_z, b.dz + lane0, N * sizeof(float));
    std::fill_n(rh.ray.tnear, N, 0.f);
    std::fill_n(rh.ray.tfar, N, std::numeric_limits<float>::infinity());
    std::fill_n(rh.ray.time, N, 0.f);
    std::fill_n(rh.ray.mask, N, 0xFFFFFFFFu);
    std::fill_n(rh.ray.id, N, 0u);
    std::fill_n(rh.ray.flags, N, 0u);
    std::fill_n(rh.hit.geomID, N, RTC_INVALID_GEOMETRY_ID);
    std::fill_n(rh.hit.instID[0], N, RTC_INVALID_GEOMETRY_ID);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    intersect(valid, rtc_scene, &context, &rh);
    for (int i = 0; i < N && lane0 + i < b.count; ++i) {
      const int l = lane0 + i;
      const unsigned prim = rh.hit.primID[i];
      if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID || prim >= prim_to_triangle.size()) {
        out.distance_mm[l] = std::numeric_limits<float>::infinity();
        out.element[l] = kNoElement;
        continue;
      }
      out.distance_mm[l] = rh.ray.tfar[i];
      out.element[l] = scene->triangle_element[prim_to_triangle[prim]];
      if (want_normals) {
        const Eigen::Vector3f dir(b.dx[l], b.dy[l], b.dz[l]);
        out.normal[l] = make_hit(rh.ray.tfar[i], prim, rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i], dir).normal;
      }
    }
  }
};

void detail::RaycasterAccess::cast_camera_block(const Raycaster& caster, const CameraBlock& b, CameraHits& out,
                                                bool want_normals) {
  const Raycaster::Impl& d = *caster.impl_;
  const int n = std::min(b.count, 16);
  switch (d.packet_width) {
    case 16: d.camera_packet<RTCRayHit16, 16>(rtcIntersect16, b, 0, out, want_normals); break;
    case 8:
      for (int l = 0; l < n; l += 8) d.camera_packet<RTCRayHit8, 8>(rtcIntersect8, b, l, out, want_normals);
      break;
    case 4:
      for (int l = 0; l < n; l += 4) d.camera_packet<RTCRayHit4, 4>(rtcIntersect4, b, l, out, want_normals);
      break;
    default:
      for (int l = 0; l < n; ++l) {
        const Hit h = d.single({b.origin, Eigen::Vector3f(b.dx[l], b.dy[l], b.dz[l])});
        out.distance_mm[l] = h.distance_mm;
        out.element[l] = h.element;
        if (want_normals) out.normal[l] = h.normal;
      }
  }
}

Raycaster::Raycaster(const Scene& scene, const std::vector<bool>& include) : Raycaster(scene, include, 0) {}

Raycaster::Raycaster(const Scene& scene, const std::vector<bool>& include, int packet_width)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.scene = &scene;
  d.include = include;
  d.include.resize(scene.elements.size(), include.empty());  // empty mask: all elements
  if (scene.triangle_element.size() != scene.triangles.size())
    throw ProcessingError("Raycaster: scene.triangle_element does not match scene.triangles");

  d.device = rtcNewDevice(nullptr);
  if (!d.device) check(nullptr, "cannot create device");
  if (packet_width == 0) {
    packet_width = rtcGetDeviceProperty(d.device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)  ? 16
                   : rtcGetDeviceProperty(d.device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) ? 8
                   : rtcGetDeviceProperty(d.device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) ? 4
                                                                                                : 1;
  }
  d.packet_width = packet_width == 16 || packet_width == 8 || packet_width == 4 ? packet_width : 1;

  d.rtc_scene = rtcNewScene(d.device);
  check(d.device, "cannot create scene");
  // Compact BVH: on the 159 k-triangle demo scene 8.7 MB instead of 14 MB (heaptrack; issue 8: inspect's peak
  // memory).
  rtcSetSceneFlags(d.rtc_scene, RTC_SCENE_FLAG_COMPACT);
  // Only included elements' triangles enter the BVH; primID maps back to the scene triangle.
  d.prim_to_triangle.reserve(scene.triangles.size());
  const int nv = static_cast<int>(scene.vertices.size());
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const std::uint32_t e = scene.triangle_element[t];
    const Eigen::Vector3i& tri = scene.triangles[t];
    if (e < d.include.size() && d.include[e] && tri.minCoeff() >= 0 && tri.maxCoeff() < nv)
      d.prim_to_triangle.push_back(static_cast<std::uint32_t>(t));
  }
  if (!d.prim_to_triangle.empty()) {
    RTCGeometry geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    check(d.device, "cannot create geometry");
    // rtcSetNewGeometryBuffer allocates with the padding Embree's SIMD loads need.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), scene.vertices.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), d.prim_to_triangle.size()));
    check(d.device, "cannot allocate geometry buffers");
    for (std::size_t i = 0; i < scene.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = scene.vertices[i][k];
    for (std::size_t p = 0; p < d.prim_to_triangle.size(); ++p)
      for (int k = 0; k < 3; ++k) idx[3 * p + k] = static_cast<unsigned>(scene.triangles[d.prim_to_triangle[p]][k]);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(d.rtc_scene, geom);
    rtcReleaseGeometry(geom);
    check(d.device, "cannot build geometry");
  }
  rtcCommitScene(d.rtc_scene);
  check(d.device, "cannot build the scene");
}

Raycaster::~Raycaster() = default;
Raycaster::Raycaster(Raycaster&&) noexcept = default;
Raycaster& Raycaster::operator=(Raycaster&&) noexcept = default;

const Scene& Raycaster::scene() const { return *impl_->scene; }
int Raycaster::packet_width() const { return impl_->packet_width; }
bool Raycaster::included(std::uint32_t element) const {
  return element < impl_->include.size() && impl_->include[element];
}

Hit Raycaster::cast(const Ray& ray) const { return impl_->single(ray); }

bool Raycaster::occluded(const Ray& ray) const {
  Eigen::Vector3f dir;
  if (!unit_direction(ray, dir)) return false;
  RTCRay r;
  r.org_x = ray.origin.x();
  r.org_y = ray.origin.y();
  r.org_z = ray.origin.z();
  r.dir_x = dir.x();
  r.dir_y = dir.y();
  r.dir_z = dir.z();
  r.tnear = 0.f;
  r.tfar = ray.tmax_mm;
  r.time = 0.f;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(impl_->rtc_scene, &context, &r);
  return r.tfar == -std::numeric_limits<float>::infinity();  // Embree marks an occluded ray so
}

void Raycaster::cast_packet(const Ray* rays, int count, Hit* hits) const {
  impl_->cast_packet(rays, std::min(count, kMaxPacket), hits, RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
}

void Raycaster::cast(const std::vector<Ray>& rays, std::vector<Hit>& hits) const {
  hits.assign(rays.size(), Hit{});
  // Fixed blocks; each ray's hit does not depend on which block or thread cast it.
  parallel_blocks(rays.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; i += kMaxPacket) {
      const int n = static_cast<int>(std::min<std::size_t>(kMaxPacket, e - i));
      impl_->cast_packet(rays.data() + i, n, hits.data() + i, RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
    }
  });
}

}  // namespace ewis
