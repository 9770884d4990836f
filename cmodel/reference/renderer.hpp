#pragma once

#include "image/image.hpp"
#include "reference/bvh.hpp"
#include "render/render.hpp"
#include "render/sampling.hpp"
#include "scene/scene.hpp"

namespace rpu {

// The ground truth for image accuracy: Whitted-style recursive ray tracing in double
// precision, exactly the shading model of docs/shading.md, over its own BVH.
class ReferenceRenderer {
 public:
  explicit ReferenceRenderer(const Scene& scene);

  // Renders the whole image on settings.threads host threads; the result does not
  // depend on the thread count. counts, if given, receives the rays traced.
  Image render(const RenderSettings& settings, RayCounts* counts = nullptr,
               const ProgressCallback& progress = {}) const;

  // Radiance along one ray that has bounced `depth` times so far.
  glm::dvec3 trace(const Ray& ray, int depth, int max_depth, SampleStream& stream, RayCounts& counts) const;

  const ReferenceBvh& bvh() const { return bvh_; }
  // Offset for secondary ray origins: 1e-4 of the scene's bounding-box diagonal.
  double ray_epsilon() const { return epsilon_; }

 private:
  glm::dvec3 shade(const Ray& ray, const Hit& hit, int depth, int max_depth, SampleStream& stream,
                   RayCounts& counts) const;

  const Scene& scene_;
  ReferenceBvh bvh_;
  double epsilon_;
};

}  // namespace rpu
