// Embree 3 wrapper: one device per process (STACK.md P16), one scene per Visibility, occlusion rays
// as segments. Life cycle as in Embree's tutorials: new device -> new scene -> attach geometry ->
// commit -> trace -> release.
#include "solver/visibility.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "solver/glazing.h"

namespace lambert {
namespace {

// The device's last error message, per thread, so that the exception thrown where the failure is
// noticed (rtcGetDeviceError after building the scene) can say what Embree said.
thread_local std::string last_embree_error;
void embree_error(void*, RTCError code, const char* message) {
  last_embree_error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

RTCDevice shared_device() {
  static std::once_flag once;
  static RTCDevice device = nullptr;
  std::call_once(once, [] {
    device = rtcNewDevice(nullptr);
    if (device) rtcSetDeviceErrorFunction(device, embree_error, nullptr);
  });
  if (!device) throw std::runtime_error("Embree device could not be created");
  return device;
}

// Flush denormals in every tracing thread (STACK.md P17); cheap and per-thread.
void set_ftz_daz() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

}  // namespace

struct Visibility::Impl {
  RTCScene scene = nullptr;           // robust (watertight)
  RTCScene estimate_scene = nullptr;  // the same geometry without robust mode, or null (Estimates)
  Point3 origin;              // re-centring offset (the scene's bounding-box centre)
  double epsilon_m = 0;       // end-point exclusion distance
  double scene_size = 1;      // bounding-box diagonal
  mutable std::atomic<std::uint64_t> rays{0};
  std::vector<int> pane_channel;  // per occluder (set_specular_panes), or empty
  std::vector<Vector3> normal;    // per occluder where panes are marked: the unit normal
  std::function<std::string(int)> pane_name;  // the surface of an occluder (set_specular_panes)

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (estimate_scene) rtcReleaseScene(estimate_scene);
  }

  void occluded(RTCScene in, std::span<const Segment> segments, std::span<std::uint8_t> visible) const;

  void fill_ray(const Point3& from, const Point3& to, RTCRay& ray) const {
    const Vector3 d = to - from;
    const double len = length(d);
    const Vector3 o = from - origin;
    ray.org_x = static_cast<float>(o.x);
    ray.org_y = static_cast<float>(o.y);
    ray.org_z = static_cast<float>(o.z);
    ray.dir_x = static_cast<float>(d.x);
    ray.dir_y = static_cast<float>(d.y);
    ray.dir_z = static_cast<float>(d.z);
    // Parametric exclusion at both ends; never more than 1 % of the segment.
    const float t_eps = len > 0 ? static_cast<float>(std::min(0.01, epsilon_m / len)) : 0.5f;
    ray.tnear = t_eps;
    ray.tfar = 1.0f - t_eps;
    ray.time = 0;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
  }
};

Visibility::Visibility(std::span<const Triangle> occluders, Estimates estimates) : impl_(std::make_shared<Impl>()) {
  RTCDevice device = shared_device();
  Bounds3 bounds;
  for (const Triangle& t : occluders)
    for (const Point3& p : t.v) bounds.add(p);
  impl_->origin = bounds.empty() ? Point3{} : bounds.center();
  const double size = bounds.empty() ? 1.0 : std::max(length(bounds.diagonal()), 1e-30);
  // Float positions carry ~3e-8 × size absolute error after re-centring; stay well above it.
  impl_->epsilon_m = 4e-6 * size;
  lift_m_ = impl_->epsilon_m;
  impl_->scene_size = size;

  impl_->scene = rtcNewScene(device);
  // Robust mode keeps shared edges watertight: a ray through the seam between two walls must not
  // slip out of a closed room (the closure probe relies on it).
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  if (!occluders.empty()) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * occluders.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), occluders.size()));
    if (!vertices || !indices) throw std::runtime_error("Embree could not allocate geometry buffers");
    for (std::size_t t = 0; t < occluders.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const Vector3 v = occluders[t].v[k] - impl_->origin;
        vertices[9 * t + 3 * k + 0] = static_cast<float>(v.x);
        vertices[9 * t + 3 * k + 1] = static_cast<float>(v.y);
        vertices[9 * t + 3 * k + 2] = static_cast<float>(v.z);
        indices[3 * t + k] = static_cast<unsigned>(3 * t + k);
      }
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    if (estimates == Estimates::fast) {  // a geometry may be attached to several scenes: one copy
      impl_->estimate_scene = rtcNewScene(device);
      rtcAttachGeometry(impl_->estimate_scene, geometry);
    }
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl_->scene);
  if (impl_->estimate_scene) rtcCommitScene(impl_->estimate_scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree failed to build the visibility scene (" + last_embree_error + ")");
}

Visibility::~Visibility() = default;

bool Visibility::visible(const Point3& from, const Point3& to) const {
  set_ftz_daz();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(16) RTCRay ray;
  impl_->fill_ray(from, to, ray);
  rtcOccluded1(impl_->scene, &context, &ray);
  impl_->rays.fetch_add(1, std::memory_order_relaxed);
  return ray.tfar >= 0;  // occlusion sets tfar = -inf
}

int Visibility::first_hit(const Point3& from, const Point3& to) const {
  set_ftz_daz();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(16) RTCRayHit rayhit;
  impl_->fill_ray(from, to, rayhit.ray);
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rayhit);
  impl_->rays.fetch_add(1, std::memory_order_relaxed);
  return rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : static_cast<int>(rayhit.hit.primID);
}

double Visibility::scene_extent() const { return 2 * impl_->scene_size; }

void Visibility::Impl::occluded(RTCScene in, std::span<const Segment> segments, std::span<std::uint8_t> visible) const {
  set_ftz_daz();
  constexpr std::size_t kStream = 256;  // rtcOccluded1M sweet spot on this machine (STACK.md §4)
  alignas(16) RTCRay stream[kStream];
  RTCIntersectContext context;
  for (std::size_t start = 0; start < segments.size(); start += kStream) {
    const std::size_t m = std::min(kStream, segments.size() - start);
    for (std::size_t k = 0; k < m; ++k) fill_ray(segments[start + k].from, segments[start + k].to, stream[k]);
    rtcInitIntersectContext(&context);
    rtcOccluded1M(in, &context, stream, static_cast<unsigned>(m), sizeof(RTCRay));
    for (std::size_t k = 0; k < m; ++k) visible[start + k] = stream[k].tfar >= 0 ? 1 : 0;
  }
  rays.fetch_add(segments.size(), std::memory_order_relaxed);
}

void Visibility::visible(std::span<const Segment> segments, std::span<std::uint8_t> visible) const {
  impl_->occluded(impl_->scene, segments, visible);
}

void Visibility::estimate_visible(std::span<const Segment> segments, std::span<std::uint8_t> visible) const {
  impl_->occluded(impl_->estimate_scene ? impl_->estimate_scene : impl_->scene, segments, visible);
}

void Visibility::first_hits(std::span<const Segment> segments, std::span<int> hits) const {
  set_ftz_daz();
  constexpr std::size_t kStream = 256;
  alignas(16) RTCRayHit rays[kStream];
  RTCIntersectContext context;
  for (std::size_t start = 0; start < segments.size(); start += kStream) {
    const std::size_t m = std::min(kStream, segments.size() - start);
    for (std::size_t k = 0; k < m; ++k) {
      impl_->fill_ray(segments[start + k].from, segments[start + k].to, rays[k].ray);
      rays[k].hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rays[k].hit.primID = RTC_INVALID_GEOMETRY_ID;
    }
    rtcInitIntersectContext(&context);
    rtcIntersect1M(impl_->scene, &context, rays, static_cast<unsigned>(m), sizeof(RTCRayHit));
    for (std::size_t k = 0; k < m; ++k)
      hits[start + k] = rays[k].hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : static_cast<int>(rays[k].hit.primID);
  }
  impl_->rays.fetch_add(segments.size(), std::memory_order_relaxed);
}

std::uint64_t Visibility::rays_traced() const { return impl_->rays.load(); }

void Visibility::set_specular_panes(std::span<const Triangle> occluders, std::vector<int> channel_of_occluder,
                                    std::function<std::string(int)> name_of) {
  impl_->normal.assign(occluders.size(), Vector3{});
  for (std::size_t t = 0; t < occluders.size(); ++t)
    if (channel_of_occluder[t] >= 0) impl_->normal[t] = occluders[t].normal();
  impl_->pane_channel = std::move(channel_of_occluder);
  impl_->pane_name = std::move(name_of);
}

std::unique_ptr<Visibility> Visibility::through_panes(int channel) const {
  std::unique_ptr<Visibility> view(new Visibility());
  view->impl_ = impl_;
  view->lift_m_ = lift_m_;
  view->channel_ = channel;
  return view;
}

double Visibility::transmitted(const Point3& from, const Point3& to) const {
  if (channel_ < 0) return visible(from, to) ? 1.0 : 0.0;
  set_ftz_daz();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(16) RTCRayHit rayhit;
  impl_->fill_ray(from, to, rayhit.ray);
  const float tfar = rayhit.ray.tfar;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rayhit);
  impl_->rays.fetch_add(1, std::memory_order_relaxed);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;  // unobstructed: not through a pane
  const unsigned first = rayhit.hit.primID;
  if (impl_->pane_channel.empty() || impl_->pane_channel[first] != channel_) return 0;
  const Vector3 d = to - from;
  const double len = length(d);
  const double g = pane_angular_factor(dot(impl_->normal[first], d) / len);
  // On beyond the pane: past its coincident other face (the same vertices, so the same distance to
  // within float precision, far below 2 ε).
  const float t_pane = rayhit.ray.tfar;
  impl_->fill_ray(from, to, rayhit.ray);
  rayhit.ray.tnear = t_pane + static_cast<float>(2 * impl_->epsilon_m / len);
  rayhit.ray.tfar = tfar;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  if (rayhit.ray.tnear < tfar) {
    rtcIntersect1(impl_->scene, &context, &rayhit);
    impl_->rays.fetch_add(1, std::memory_order_relaxed);
  }
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return g;
  if (impl_->pane_channel[rayhit.hit.primID] >= 0) {
    const auto name = [&](unsigned t) {
      return impl_->pane_name ? "'" + impl_->pane_name(static_cast<int>(t)) + "'" : "occluder " + std::to_string(t);
    };
    throw std::invalid_argument("a ray from a source crosses two specular panes, surfaces " + name(first) + " and " +
                                name(rayhit.hit.primID) +
                                "; clear glass is supported where light crosses at most one pane (model a "
                                "double-glazed unit as one pane with the unit's transmittance)");
  }
  return 0;
}

}  // namespace lambert
