#pragma once
// spdlog set-up shared by every tool: human-readable lines or JSON lines (--log-json) on stderr.

#include <string>

namespace surfcap::core {

struct LogOptions {
  std::string level = "info";  ///< trace, debug, info, warn, error, critical, off
  bool json = false;           ///< one JSON object per line, for farms
};

/// Installs the default logger; bad_arguments (2) for an unknown level.
void configure_logging(const LogOptions& options);

/// Escapes `text` as the body of a JSON string (no quotes added).
std::string json_escape(const std::string& text);

}  // namespace surfcap::core
