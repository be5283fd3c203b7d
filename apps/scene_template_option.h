#ifndef BOUNCECAL_APPS_SCENE_TEMPLATE_OPTION_H_
#define BOUNCECAL_APPS_SCENE_TEMPLATE_OPTION_H_

#include <CLI/CLI.hpp>
#include <string>

namespace bouncecal::apps {

// `pack --template NAME`: write a commented scene file (dem::SceneTemplates) to stdout instead of
// running one, so a new scene starts from a complete, explained file.
CLI::Option* AddSceneTemplateOption(CLI::App& command, std::string& name);
// Writes the template to stdout; a ConfigError naming the templates there are when unknown.
void WriteSceneTemplate(const std::string& name);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_SCENE_TEMPLATE_OPTION_H_
