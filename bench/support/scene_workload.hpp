#pragma once

#include <map>
#include <memory>
#include <string>

#include "functional/scene_image.hpp"
#include "scene/resolve.hpp"

namespace rpu::bench {

// A scene and its memory image for the `default` configuration (Woop records), built
// once per name for all benchmarks of a program.
struct SceneWorkload {
  Scene scene;
  functional::SceneImage image;
};

inline const SceneWorkload& scene_workload(const std::string& name) {
  static std::map<std::string, std::unique_ptr<SceneWorkload>> cache;
  auto& w = cache[name];
  if (!w) {
    w = std::make_unique<SceneWorkload>();
    w->scene = resolve_scene(name);
    w->image = functional::make_scene_image(w->scene, kd_build_config_for("default"), IsectMode::kWoop);
  }
  return *w;
}

}  // namespace rpu::bench
