#include "scene_template_option.h"

#include <fmt/core.h>

#include "bouncecal/dem/scene_templates.h"
#include "bouncecal/error.h"
#include "option_names.h"
#include "output_target.h"

namespace bouncecal::apps {
namespace {

std::string TemplateList(std::string_view separator) {
  std::string list;
  for (const auto& scene : dem::SceneTemplates()) {
    list += fmt::format("{}{} ({})", list.empty() ? "" : separator, scene.name, scene.summary);
  }
  return list;
}

}  // namespace

CLI::Option* AddSceneTemplateOption(CLI::App& command, std::string& name) {
  return command.add_option(
      "--template", name,
      "Write a commented scene file to stdout instead of running one, e.g. bouncecal pack "
      "--template 3d-cylinder > scene.json; templates: " +
          TemplateList("; "));
}

void WriteSceneTemplate(const std::string& name) {
  const auto scene = dem::FindSceneTemplate(name);
  if (!scene) {
    throw ConfigError(
        fmt::format("--template: no template '{}'; there are: {}", name, TemplateList(", ")));
  }
  // The template's comments name the command's options in backticks, as library text does.
  WriteTextOutput("-", WithFlags(scene->text));
}

}  // namespace bouncecal::apps
