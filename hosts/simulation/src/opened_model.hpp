// What every run of one model shares and none changes: the model's text with
// the settings it was opened with, the parsed model file, its plugins and
// the run choices. An Instance holds one for itself; a Batch one for all its
// runs, so a run costs its simulation and not another parse and plugin load.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh::embed {

// What a setting chooses as the command line's flags do; the rest are
// paths into the model's tree.
struct OpenRequest {
  std::string path;                   // the model file ("" when from text)
  std::string text, label, base_dir;  // the model's text, when not from a file
  std::vector<std::pair<std::string, std::string>> settings;
};

struct OpenedModel {
  // Throws InputError, PluginError or std::exception naming what is wrong.
  explicit OpenedModel(const OpenRequest& request);
  OpenedModel(const OpenedModel&) = delete;
  OpenedModel& operator=(const OpenedModel&) = delete;

  std::string text;      // the model's text with the opening settings
  std::string label;     // its name in messages: the file's path, or the text's label
  std::string base_dir;  // where its relative paths start
  RunChoices choices;
  ModelFile file;
  PluginRegistry registry;
};

// One run's model as its file would now read: the opened model's text and
// bodies with every value the run changed in place since.
struct ChangedModel {
  explicit ChangedModel(const OpenedModel& opened) : text(opened.text), model(opened.file.model) {}
  std::string text;
  Model model;
};

// A value of the model changed in place in `sim`, a run of `opened`, before
// its start or between steps (mhs_set_parameter): a body's mass, centre of
// mass, inertia or payload, gravity, a component's option it changes in place
// (monohydra/parameters.h), or before the start a body's z0 and zd0, by its
// path as settings address it, the value as the model file would write it.
// The file's parser reads the run's text with the value, so a value is
// checked and derived (an inertia from a shape) as when opening. Throws
// std::invalid_argument naming the path; nothing changes.
void set_parameter(Simulation& sim, const OpenedModel& opened, ChangedModel& run,
                   const std::string& path, const std::string& value);

}  // namespace mh::embed
