#pragma once
// The command-line conventions every surfcap tool shares (docs/cli.md): --help with defaults,
// --version, --config file.json, --threads, --log-level, --log-json, and exit codes.

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "surfcap/core/json_document.hpp"
#include "surfcap/core/logging.hpp"

namespace surfcap::core {

struct CommonOptions {
  int threads = 0;  ///< 0: all hardware threads
  LogOptions log;
  std::string config;  ///< --config file the options were read from, if any
  std::string max_memory = "0";  ///< --max-memory as given (bytes or K/M/G/T; 0: half of the physical memory)
};

/// Reads --config files: a JSON object whose keys are long option names (without "--"),
/// nested objects for subcommands, e.g. {"threads": 2, "similarity": {"rows": "0:100"}}.
class JsonConfig : public CLI::Config {
 public:
  std::string to_config(const CLI::App* app, bool default_also, bool write_description,
                        std::string prefix) const override;
  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override;
};

class ToolApp {
 public:
  ToolApp(std::string name, std::string description);

  CLI::App& cli() { return app_; }
  const CommonOptions& common() const { return common_; }
  /// The effective options (command line + config + defaults) as JSON, for reports.
  Json options_json() const;
  /// options_json() without those that cannot change an output (--threads, logging): what
  /// output files record as provenance, so their bytes do not depend on the thread count.
  Json provenance_json() const;

  /// Parses the command line, configures logging and threads, then runs `body`. Returns the
  /// process exit code: 0 ok (and --help/--version), 2 bad arguments, and for a thrown
  /// core::Error its code (3 bad input, 4 I/O); 1 for anything unexpected.
  int run(int argc, const char* const* argv, const std::function<void()>& body);

 private:
  CLI::App app_;
  CommonOptions common_;
};

}  // namespace surfcap::core
