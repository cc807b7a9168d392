#include "surfcap/asset/character.hpp"

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/graph/transition_files.hpp"

namespace surfcap::asset {

int Character::space_index(const std::string& space) const {
  for (std::size_t i = 0; i < spaces.size(); ++i)
    if (spaces[i].name == space) return static_cast<int>(i);
  return -1;
}

const CharacterTransition* Character::find_transition(const std::string& from, const std::string& to) const {
  for (const CharacterTransition& transition : transitions)
    if (transition.from == from && transition.to == to) return &transition;
  return nullptr;
}

namespace {

/// Every source of `space` must be a database sequence long enough for its frame range.
void check_sources(const CharacterSpace& space, const core::AlignedDatabase& database, const std::filesystem::path& graph) {
  for (const SpaceSource& source : space.sources) {
    const int index = database.sequence_index(source.sequence);
    if (index < 0)
      throw core::bad_input(graph, "space '" + space.name + "' uses sequence '" + source.sequence +
                                       "', which the database does not hold");
    const int available = database.sequences[index].frame_count();
    if (source.first < 0 || source.first + source.frames > available)
      throw core::bad_input(graph, "space '" + space.name + "': frames " + std::to_string(source.first) + "+" +
                                       std::to_string(source.frames) + " of '" + source.sequence +
                                       "' exceed its " + std::to_string(available) + " frames");
  }
}

}  // namespace

Character assemble_character(const CharacterInputs& inputs) {
  Character character;
  character.name = inputs.name;
  core::AlignedDatabase database = core::read_database(inputs.database);
  character.template_mesh = std::move(database.template_mesh);
  character.fps = database.fps;
  character.units = database.units;
  const long V = character.vertex_count();

  const core::Json graph = core::read_json_document(inputs.graph, "graph", 1);
  const std::filesystem::path output = inputs.graph.parent_path();
  for (const core::Json& entry : core::get_field<core::Json>(graph, "spaces", inputs.graph)) {
    CharacterSpace space = blend::stored_space_from_entry(entry, output, inputs.graph, V);
    if (character.space_index(space.name) >= 0) throw core::bad_input(inputs.graph, "space '" + space.name + "' appears twice");
    check_sources(space, database, inputs.graph);
    character.spaces.push_back(std::move(space));
  }
  if (character.spaces.empty()) throw core::bad_input(inputs.graph, "declares no motion space");

  for (const core::Json& entry : graph.value("transitions", core::Json::array())) {
    CharacterTransition transition;
    transition.from = core::name_field(entry, "from", inputs.graph);  // they name the transition's file
    transition.to = core::name_field(entry, "to", inputs.graph);
    const int from = character.space_index(transition.from), to = character.space_index(transition.to);
    if (from < 0 || to < 0)
      throw core::bad_input(inputs.graph, "transition " + transition.from + " → " + transition.to + " names an undeclared space");
    if (character.find_transition(transition.from, transition.to))
      throw core::bad_input(inputs.graph, "transition " + transition.from + " → " + transition.to + " appears twice");
    transition.rows = character.spaces[from].node_count() * character.spaces[from].frames;
    transition.cols = character.spaces[to].node_count() * character.spaces[to].frames;
    transition.similarity =
        graph::read_transition_similarity(output, transition.from, transition.to, transition.rows, transition.cols);
    character.transitions.push_back(std::move(transition));
  }

  if (!inputs.parts.empty()) {
    learn::LearntModel parts = learn::read_learnt_model(inputs.parts);
    if (parts.template_mesh.V.rows() != V || parts.template_mesh.F.rows() != character.template_mesh.F.rows())
      throw core::bad_input(inputs.parts, "part models are of a " + std::to_string(parts.template_mesh.V.rows()) +
                                              "-vertex template, the database's has " + std::to_string(V));
    character.parts = std::move(parts);
  }
  character.sequences = std::move(database.sequences);
  character.provenance = {{"tool", "surfcap assemble_character"},
                          {"version", core::version()},
                          {"database", inputs.database.generic_string()},
                          {"graph", inputs.graph.generic_string()},
                          {"parts", inputs.parts.generic_string()},
                          {"graph_provenance", graph.value("provenance", core::Json::object())}};
  return character;
}

}  // namespace surfcap::asset
