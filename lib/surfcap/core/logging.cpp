#include "surfcap/core/logging.hpp"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <ctime>

#include "surfcap/core/error.hpp"

namespace surfcap::core {
namespace {

/// {"time":"2026-11-25T10:00:00.123Z","level":"info","logger":"surfcap","message":"..."}
class JsonFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& message, spdlog::memory_buf_t& destination) override {
    const auto time = std::chrono::system_clock::to_time_t(message.time);
    const auto millis =
        std::chrono::duration_cast<std::chrono::milliseconds>(message.time.time_since_epoch()).count() % 1000;
    std::tm utc{};
    gmtime_r(&time, &utc);
    char stamp[80];
    std::snprintf(stamp, sizeof stamp, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900, utc.tm_mon + 1,
                  utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, static_cast<int>(millis));
    const auto level = spdlog::level::to_string_view(message.level);
    const std::string text(message.payload.begin(), message.payload.end());
    const std::string line = std::string("{\"time\":\"") + stamp + "\",\"level\":\"" +
                             std::string(level.begin(), level.end()) + "\",\"logger\":\"" +
                             std::string(message.logger_name.begin(), message.logger_name.end()) +
                             "\",\"message\":\"" + json_escape(text) + "\"}\n";
    destination.append(line.data(), line.data() + line.size());
  }
  std::unique_ptr<spdlog::formatter> clone() const override { return std::make_unique<JsonFormatter>(); }
};

}  // namespace

std::string json_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size() + 8);
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  return out;
}

void configure_logging(const LogOptions& options) {
  const auto level = spdlog::level::from_str(options.level);
  if (level == spdlog::level::off && options.level != "off")
    throw bad_arguments("--log-level '" + options.level + "': expected trace, debug, info, warn, error, critical or off");
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>(
      options.json ? spdlog::color_mode::never : spdlog::color_mode::automatic);
  auto logger = std::make_shared<spdlog::logger>("surfcap", sink);
  if (options.json)
    logger->set_formatter(std::make_unique<JsonFormatter>());
  else
    logger->set_pattern("%^[%H:%M:%S.%e %l]%$ %v");
  logger->set_level(level);
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(logger);
}

}  // namespace surfcap::core
