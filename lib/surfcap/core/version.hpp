#pragma once
#include <string_view>

namespace surfcap::core {
/// "0.1.0+<git describe>" baked in at configure time; written into --version and every provenance.
std::string_view version();
}  // namespace surfcap::core
