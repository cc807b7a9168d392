#pragma once
// surfcap-align import-cameras / import-capture (docs/cli.md): calibrations and folders of
// numbered reconstructions as studios hand them over, turned into cameras.json and capture.json.

#include <memory>

#include "surfcap/core/cli.hpp"

namespace surfcap::tools {

class ImportCommands {
 public:
  /// Adds the "import-cameras" and "import-capture" subcommands to app.cli().
  explicit ImportCommands(core::ToolApp& app);
  ~ImportCommands();
  /// Runs whichever of them was selected (nothing otherwise).
  void run() const;
  struct State;  ///< parsed options (import_command.cpp)

 private:
  core::ToolApp& app_;
  std::unique_ptr<State> state_;
};

}  // namespace surfcap::tools
