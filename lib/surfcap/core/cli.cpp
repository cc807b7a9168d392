#include "surfcap/core/cli.hpp"

#include <Eigen/Core>
#include <omp.h>
#include <spdlog/spdlog.h>

#include <csignal>
#include <iostream>
#include <new>
#include <sstream>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/core/version.hpp"

namespace surfcap::core {
namespace {

void flatten(const Json& object, std::vector<std::string>& parents, std::vector<CLI::ConfigItem>& items) {
  for (const auto& [key, value] : object.items()) {
    if (value.is_object()) {
      parents.push_back(key);
      flatten(value, parents, items);
      parents.pop_back();
      continue;
    }
    CLI::ConfigItem item;
    item.parents = parents;
    item.name = key;
    auto as_text = [](const Json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); };
    if (value.is_array()) {
      for (const auto& element : value) item.inputs.push_back(as_text(element));
    } else if (!value.is_null()) {
      item.inputs.push_back(as_text(value));
    }
    items.push_back(std::move(item));
  }
}

Json option_value(const CLI::Option* option) {
  const auto& results = option->results();
  std::vector<std::string> values = results;
  if (values.empty()) {
    const std::string fallback = option->get_default_str();
    if (fallback.empty()) return nullptr;
    values.push_back(fallback);
  }
  auto convert = [](const std::string& text) -> Json {
    const Json parsed = Json::parse(text, nullptr, false);
    if (!parsed.is_discarded() && (parsed.is_number() || parsed.is_boolean())) return parsed;
    return text;
  };
  if (option->get_expected_max() > 1 && values.size() != 1) {
    Json array = Json::array();
    for (const auto& value : values) array.push_back(convert(value));
    return array;
  }
  if (option->get_type_size() == 0) {  // a flag
    return results.empty() ? Json(false) : Json(option->as<bool>());
  }
  return convert(values.back());
}

Json app_options(const CLI::App* app) {
  Json object = Json::object();
  for (const CLI::Option* option : app->get_options()) {
    const std::string name = option->get_single_name();
    if (name.empty() || name == "help" || name == "version" || name == "config") continue;
    if (option->get_lnames().empty()) continue;
    Json value = option_value(option);
    if (!value.is_null()) object[option->get_lnames().front()] = std::move(value);
  }
  for (const CLI::App* sub : app->get_subcommands({})) {
    if (sub->parsed()) object[sub->get_name()] = app_options(sub);
  }
  return object;
}

}  // namespace

std::string JsonConfig::to_config(const CLI::App* app, bool, bool, std::string) const {
  return app_options(app).dump(2) + "\n";
}

std::vector<CLI::ConfigItem> JsonConfig::from_config(std::istream& input) const {
  std::stringstream buffer;
  buffer << input.rdbuf();
  Json document;
  try {
    document = parse_json_text(buffer.str(), "--config");
  } catch (const Error& e) {
    throw bad_arguments(std::string("--config: ") + e.what());
  }
  if (!document.is_object()) throw bad_arguments("--config: the file is not a JSON object of option names to values");
  std::vector<CLI::ConfigItem> items;
  std::vector<std::string> parents;
  flatten(document, parents, items);
  return items;
}

ToolApp::ToolApp(std::string name, std::string description) : app_(std::move(description), std::move(name)) {
  app_.option_defaults()->always_capture_default();
  app_.fallthrough();  // subcommands inherit it: common options may follow the subcommand
  app_.set_version_flag("--version", std::string(version()));
  app_.config_formatter(std::make_shared<JsonConfig>());
  app_.allow_config_extras(CLI::config_extras_mode::error);
  app_.set_config("--config", "", "JSON file holding option values (keys: long option names)")
      ->check(CLI::ExistingFile);
  app_.add_option("--threads", common_.threads, "Worker threads (0: all hardware threads)")
      ->check(CLI::NonNegativeNumber);
  app_.add_option("--log-level", common_.log.level, "trace, debug, info, warn, error, critical or off");
  app_.add_flag("--log-json", common_.log.json, "Log one JSON object per line (for farms)");
  app_.add_option("--max-memory", common_.max_memory,
                  "Memory budget for what input files request, e.g. 8G (0: half of the physical memory); "
                  "larger requests are bad input (exit 3)");
  app_.add_flag("--allow-outside-paths", input_policy().allow_outside_paths,
                "Let input documents name absolute paths and paths outside their folder (refused otherwise, exit 3)");
}

Json ToolApp::options_json() const { return app_options(&app_); }

Json ToolApp::provenance_json() const {
  Json options = options_json();
  for (const char* run_only : {"threads", "log-level", "log-json", "max-memory", "allow-outside-paths"})
    options.erase(run_only);
  return options;
}

int ToolApp::run(int argc, const char* const* argv, const std::function<void()>& body) {
  // Writes past RLIMIT_FSIZE must fail with EFBIG (exit 4), not kill the process.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    app_.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app_.exit(e);
  } catch (const CLI::ParseError& e) {
    app_.exit(e);
    return static_cast<int>(ExitCode::bad_arguments);
  } catch (const Error& e) {
    std::cerr << app_.get_name() << ": " << e.what() << "\n";
    return e.exit_code();
  }
  if (auto* option = app_.get_config_ptr(); option && option->count() > 0) common_.config = option->as<std::string>();
  try {
    input_policy().max_memory_bytes = parse_memory_size(common_.max_memory);
  } catch (const Error& e) {
    std::cerr << app_.get_name() << ": " << e.what() << "\n";
    return e.exit_code();
  }
  try {
    configure_logging(common_.log);
    const int threads = resolve_threads(common_.threads);
    omp_set_num_threads(threads);
    Eigen::setNbThreads(threads);
    body();
    spdlog::default_logger()->flush();
    return 0;
  } catch (const Error& e) {
    spdlog::error("{}", e.what());
    spdlog::default_logger()->flush();
    return e.exit_code();
  } catch (const nlohmann::json::exception& e) {
    // A JSON reader that did not check a field's type: still the input's fault.
    spdlog::error("invalid JSON content: {}", json_error_text(e));
    return static_cast<int>(ExitCode::bad_input);
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory");
    return static_cast<int>(ExitCode::internal);
  } catch (const std::exception& e) {
    spdlog::error("internal error: {}", e.what());
    return static_cast<int>(ExitCode::internal);
  }
}

}  // namespace surfcap::core
