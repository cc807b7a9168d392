#include <gtest/gtest.h>

#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/version.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

/// Runs a ToolApp with `args`; the body throws `thrown` (or nothing). Returns the exit code.
int run_tool(std::vector<std::string> args, const std::function<void()>& body, double* tolerance = nullptr,
             core::CommonOptions* common = nullptr) {
  core::ToolApp app("surfcap-test", "test tool");
  double value = 5.0;
  app.cli().add_option("--tolerance-mm", value, "Tolerance in mm");
  args.insert(args.begin(), "surfcap-test");
  std::vector<const char*> argv;
  for (const auto& arg : args) argv.push_back(arg.c_str());
  const int code = app.run(static_cast<int>(argv.size()), argv.data(), body);
  if (tolerance) *tolerance = value;
  if (common) *common = app.common();
  return code;
}

TEST(Cli, ExitCodesFollowTheErrorType) {
  EXPECT_EQ(run_tool({}, [] {}), 0);
  EXPECT_EQ(run_tool({}, [] { throw core::bad_input("f.ply", "broken", 3); }), 3);
  EXPECT_EQ(run_tool({}, [] { throw core::io_error("f.ply", "disk full"); }), 4);
  EXPECT_EQ(run_tool({}, [] { throw core::bad_arguments("no"); }), 2);
  EXPECT_EQ(run_tool({}, [] { throw std::runtime_error("bug"); }), 1);
  EXPECT_EQ(run_tool({"--no-such-option"}, [] {}), 2);
  EXPECT_EQ(run_tool({"--tolerance-mm", "abc"}, [] {}), 2);
  EXPECT_EQ(run_tool({"--log-level", "loud"}, [] {}), 2);
  EXPECT_EQ(run_tool({"--threads", "-3"}, [] {}), 2);
}

TEST(Cli, HelpAndVersionExitZeroWithoutRunning) {
  bool ran = false;
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(run_tool({"--help"}, [&] { ran = true; }), 0);
  const std::string help = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(help.find("--tolerance-mm"), std::string::npos);
  EXPECT_NE(help.find("5"), std::string::npos);  // the default is shown
  EXPECT_NE(help.find("--log-json"), std::string::npos);
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(run_tool({"--version"}, [&] { ran = true; }), 0);
  EXPECT_NE(::testing::internal::GetCapturedStdout().find(std::string(core::version())), std::string::npos);
  EXPECT_FALSE(ran);
}

TEST(Cli, ConfigFileSetsOptionsAndCommandLineWins) {
  testing::TemporaryDirectory dir("cli_config");
  testing::write_text(dir / "c.json", R"({"tolerance-mm": 2.5, "threads": 3})");
  double tolerance = 0;
  core::CommonOptions common;
  EXPECT_EQ(run_tool({"--config", (dir / "c.json").string()}, [] {}, &tolerance, &common), 0);
  EXPECT_DOUBLE_EQ(tolerance, 2.5);
  EXPECT_EQ(common.threads, 3);
  EXPECT_EQ(run_tool({"--config", (dir / "c.json").string(), "--tolerance-mm", "1"}, [] {}, &tolerance), 0);
  EXPECT_DOUBLE_EQ(tolerance, 1.0);
  testing::write_text(dir / "bad.json", "{not json");
  EXPECT_EQ(run_tool({"--config", (dir / "bad.json").string()}, [] {}), 2);
  testing::write_text(dir / "unknown.json", R"({"frobnicate": 1})");
  EXPECT_EQ(run_tool({"--config", (dir / "unknown.json").string()}, [] {}), 2);
  EXPECT_EQ(run_tool({"--config", (dir / "absent.json").string()}, [] {}), 2);
}

TEST(Cli, OptionsJsonMirrorsEffectiveValues) {
  core::ToolApp app("surfcap-test", "test tool");
  double tolerance = 5.0;
  app.cli().add_option("--tolerance-mm", tolerance, "Tolerance in mm");
  const char* argv[] = {"surfcap-test", "--tolerance-mm", "7", "--threads", "2"};
  core::Json options;
  EXPECT_EQ(app.run(5, argv, [&] { options = app.options_json(); }), 0);
  EXPECT_EQ(options["tolerance-mm"], 7);
  EXPECT_EQ(options["threads"], 2);
  EXPECT_EQ(options["log-level"], "info");
}

TEST(Cli, ProvenanceLeavesOutWhatCannotChangeAnOutput) {
  core::ToolApp app("surfcap-test", "test tool");
  double tolerance = 5.0;
  app.cli().add_option("--tolerance-mm", tolerance, "Tolerance in mm");
  const char* argv[] = {"surfcap-test", "--tolerance-mm", "7", "--threads", "2", "--log-level", "warn"};
  core::Json options;
  EXPECT_EQ(app.run(7, argv, [&] { options = app.provenance_json(); }), 0);
  EXPECT_EQ(options["tolerance-mm"], 7);
  EXPECT_FALSE(options.contains("threads"));
  EXPECT_FALSE(options.contains("log-level"));
  EXPECT_FALSE(options.contains("log-json"));
}

TEST(Cli, MaxMemoryBelongsToItsApp) {
  core::CommonOptions first, second;
  EXPECT_EQ(run_tool({"--max-memory", "1G"}, [] {}, nullptr, &first), 0);
  EXPECT_EQ(first.max_memory, "1G");
  EXPECT_EQ(core::input_policy().max_memory_bytes, std::uint64_t{1} << 30);
  // A later app starts from the default, not from the value the first one parsed.
  EXPECT_EQ(run_tool({}, [] {}, nullptr, &second), 0);
  EXPECT_EQ(second.max_memory, "0");
  EXPECT_EQ(core::input_policy().max_memory_bytes, 0u);
}

}  // namespace
}  // namespace surfcap
