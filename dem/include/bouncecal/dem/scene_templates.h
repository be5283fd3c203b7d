#ifndef BOUNCECAL_DEM_SCENE_TEMPLATES_H_
#define BOUNCECAL_DEM_SCENE_TEMPLATES_H_

#include <optional>
#include <span>
#include <string_view>

namespace bouncecal::dem {

// Commented starting points for a scene file (`bouncecal pack --template NAME > scene.json`):
// complete scenes that load, run without a warning about their own set-up, and explain every key
// in "_comment" keys, which the scene reader skips (docs/scenes.md).
struct SceneTemplate {
  std::string_view name;     // "3d-cylinder"
  std::string_view summary;  // one line for --help
  std::string_view text;     // the scene JSON
};

std::span<const SceneTemplate> SceneTemplates();
std::optional<SceneTemplate> FindSceneTemplate(std::string_view name);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_SCENE_TEMPLATES_H_
