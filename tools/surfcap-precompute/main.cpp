// surfcap-precompute: motion spaces and transitions from an aligned database.
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
  surfcap::core::ToolApp app("surfcap-precompute",
                             "Precompute parametric motion spaces and transitions from an aligned database");
  app.cli().require_subcommand(1);
  std::vector<surfcap::tools::Command> commands;
  commands.push_back(surfcap::tools::add_spaces_command(app));
  commands.push_back(surfcap::tools::add_graph_command(app));
  commands.push_back(surfcap::tools::add_compare_command(app));
  commands.push_back(surfcap::tools::add_transitions_command(app));
  return app.run(argc, argv, [&] {
    for (const auto& [command, run] : commands)
      if (command->parsed()) run();
  });
}
