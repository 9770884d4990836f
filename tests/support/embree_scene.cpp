#include "embree_scene.hpp"

namespace rpu::test {

EmbreeScene::EmbreeScene(const Scene& scene) {
  device_ = rtcNewDevice("threads=1");
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), scene.positions.size()));
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    for (int c = 0; c < 3; ++c) v[3 * i + c] = scene.positions[i][c];
  }
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), scene.triangles.size()));
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    for (int c = 0; c < 3; ++c) t[3 * i + c] = scene.triangles[i][c];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_);
}

EmbreeScene::~EmbreeScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

std::tuple<bool, float, unsigned> EmbreeScene::intersect(const functional::TraceRay& r) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = r.origin[0];
  rh.ray.org_y = r.origin[1];
  rh.ray.org_z = r.origin[2];
  rh.ray.dir_x = r.direction[0];
  rh.ray.dir_y = r.direction[1];
  rh.ray.dir_z = r.direction[2];
  rh.ray.tnear = r.t_min;
  rh.ray.tfar = r.t_max;
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  return {rh.hit.geomID != RTC_INVALID_GEOMETRY_ID, rh.ray.tfar, rh.hit.primID};
}

}  // namespace rpu::test
