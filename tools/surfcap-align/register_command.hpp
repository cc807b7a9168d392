#pragma once
// surfcap-align register / run (docs/align.md): the non-rigid alignment along the shape
// similarity tree, and the whole capture → database chain in one go.

#include <memory>
#include <string>

#include "surfcap/core/cli.hpp"

namespace surfcap::tools {

/// --root and --root-candidates (the tree's root frame), shared by "tree" and "run".
void add_root_options(CLI::App* command, std::string& root, double& root_candidates);

class RegisterCommands {
 public:
  /// Adds the "register" and "run" subcommands to app.cli().
  explicit RegisterCommands(core::ToolApp& app);
  ~RegisterCommands();
  /// Runs whichever of them was selected (nothing otherwise).
  void run() const;
  struct State;  ///< parsed options (register_command.cpp)

 private:
  core::ToolApp& app_;
  std::unique_ptr<State> state_;
};

}  // namespace surfcap::tools
