#pragma once

// Embree 3 as an independent oracle and speed reference, for tests and benchmarks
// only: it never links into the model.
#include <tuple>

#include <embree3/rtcore.h>

#include "functional/trace_types.hpp"
#include "scene/scene.hpp"

namespace rpu::test {

class EmbreeScene {
 public:
  explicit EmbreeScene(const Scene& scene);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Closest hit with rtcIntersect1: (hit, t, prim).
  std::tuple<bool, float, unsigned> intersect(const functional::TraceRay& r) const;

 private:
  RTCDevice device_;
  RTCScene scene_;
};

}  // namespace rpu::test
