#include "surfcap/graph/graph_config.hpp"

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::graph {

const blend::SpaceConfig* GraphConfig::find(const std::string& name) const {
  for (const auto& space : spaces)
    if (space.name == name) return &space;
  return nullptr;
}

GraphConfig read_graph_config(const std::filesystem::path& path) {
  const core::Json json = core::read_json_document(path, "graph_config", 1);
  GraphConfig config;
  try {
    for (const auto& item : json.at("spaces")) {
      blend::SpaceConfig space = blend::parse_space_config(item, path);
      if (config.find(space.name)) throw core::bad_input(path, "space '" + space.name + "' declared twice");
      config.spaces.push_back(std::move(space));
    }
    for (const auto& item : json.value("transitions", core::Json::array()))
      config.transitions.push_back({item.at("from").get<std::string>(), item.at("to").get<std::string>()});
  } catch (const core::Json::exception& error) {
    throw core::bad_input(path, "malformed graph config: " + core::json_error_text(error));
  } catch (const core::Error& error) {
    if (error.code() == core::ExitCode::bad_arguments) throw core::bad_input(path, error.what());
    throw;
  }
  for (const auto& transition : config.transitions)
    if (!config.find(transition.from) || !config.find(transition.to))
      throw core::bad_input(path, "transition " + transition.from + " → " + transition.to + " names an unknown space");
  return config;
}

}  // namespace surfcap::graph
