#include <gtest/gtest.h>

#include <cstdint>
#include <functional>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::TemporaryDirectory;
using testing::write_text;

std::string error_of(const std::filesystem::path& path, std::string_view kind, int version,
                     core::ExitCode expected = core::ExitCode::bad_input) {
  try {
    core::read_json_document(path, kind, version);
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), expected) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return {};
}

TEST(JsonDocument, RoundTripIsSortedAndDeterministic) {
  TemporaryDirectory dir("json_round_trip");
  core::Json document = {{"format", core::format_tag("capture", 1)}, {"zeta", 1}, {"alpha", {1.5, 2}}};
  core::write_json_file(dir / "a.json", document);
  const std::string text = core::read_file(dir / "a.json");
  EXPECT_LT(text.find("alpha"), text.find("zeta"));
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(core::read_json_document(dir / "a.json", "capture", 1), document);
  EXPECT_EQ(core::document_version(document), 1);
}

TEST(JsonDocument, FormatChecks) {
  TemporaryDirectory dir("json_format");
  write_text(dir / "newer.json", R"({"format": "surfcap.capture/3"})");
  EXPECT_NE(error_of(dir / "newer.json", "capture", 1).find("newer than this build reads"), std::string::npos);
  write_text(dir / "other.json", R"({"format": "surfcap.graph/1"})");
  EXPECT_NE(error_of(dir / "other.json", "capture", 1).find("is a surfcap.graph file"), std::string::npos);
  write_text(dir / "none.json", R"({"name": "x"})");
  EXPECT_NE(error_of(dir / "none.json", "capture", 1).find("missing \"format\""), std::string::npos);
  write_text(dir / "odd.json", R"({"format": "mesh"})");
  EXPECT_NE(error_of(dir / "odd.json", "capture", 1).find("odd.json"), std::string::npos);
  write_text(dir / "array.json", "[1, 2]");
  EXPECT_NE(error_of(dir / "array.json", "capture", 1).find("JSON object"), std::string::npos);
  write_text(dir / "ok2.json", R"({"format": "surfcap.capture/2"})");
  EXPECT_EQ(core::document_version(core::read_json_document(dir / "ok2.json", "capture", 2)), 2);
}

TEST(JsonDocument, SyntaxErrorGivesLineAndColumn) {
  TemporaryDirectory dir("json_syntax");
  write_text(dir / "broken.json", "{\n  \"format\": \"surfcap.capture/1\",\n  \"fps\": ,\n}\n");
  const std::string message = error_of(dir / "broken.json", "capture", 1);
  EXPECT_NE(message.find("broken.json"), std::string::npos);
  EXPECT_NE(message.find("line 3"), std::string::npos) << message;
}

TEST(JsonDocument, MissingFileIsIoError) {
  TemporaryDirectory dir("json_missing");
  error_of(dir / "absent.json", "capture", 1, core::ExitCode::io);
}

TEST(JsonDocument, FieldAccessNamesTheField) {
  const core::Json object = {{"fps", "fast"}};
  try {
    core::get_field<double>(object, "fps", "capture.json");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"fps\""), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("capture.json"), std::string::npos);
  }
  EXPECT_THROW(core::get_field<int>(object, "count", "capture.json"), core::Error);
}

TEST(JsonDocument, IntegerFieldsTakeOnlyIntegersWithinTheType) {
  const core::Json object = core::Json::parse(R"({"first": 1.5, "whole": 2.0, "exponent": 1e3, "flag": true,
    "big": 3000000000, "negative": -1, "huge": 18446744073709551615, "count": 7, "name": "seven"})");
  const auto expect_refused = [&](const std::function<void()>& read, const std::string& field, const std::string& got) {
    try {
      read();
      ADD_FAILURE() << field << " was accepted";
    } catch (const core::Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.code(), core::ExitCode::bad_input) << message;
      EXPECT_NE(message.find("capture.json"), std::string::npos) << message;
      EXPECT_NE(message.find("\"" + field + "\""), std::string::npos) << message;
      EXPECT_NE(message.find(got), std::string::npos) << message;
    }
  };
  // Floats are never truncated, whether or not they are whole; booleans are not numbers.
  expect_refused([&] { core::get_field<int>(object, "first", "capture.json"); }, "first", "got 1.5");
  expect_refused([&] { core::get_field<int>(object, "whole", "capture.json"); }, "whole", "got 2.0");
  expect_refused([&] { core::get_field<long>(object, "exponent", "capture.json"); }, "exponent", "got 1000.0");
  expect_refused([&] { core::get_field<std::int64_t>(object, "flag", "capture.json"); }, "flag", "got true");
  expect_refused([&] { core::get_field<std::size_t>(object, "first", "capture.json"); }, "first", "got 1.5");
  // Integers must fit the type: no wrapping.
  expect_refused([&] { core::get_field<int>(object, "big", "capture.json"); }, "big", "got 3000000000");
  expect_refused([&] { core::get_field<unsigned>(object, "negative", "capture.json"); }, "negative", "got -1");
  expect_refused([&] { core::get_field<std::size_t>(object, "negative", "capture.json"); }, "negative", "got -1");
  expect_refused([&] { core::get_field<std::int64_t>(object, "huge", "capture.json"); }, "huge",
                 "got 18446744073709551615");
  expect_refused([&] { core::get_field<std::uint32_t>(object, "huge", "capture.json"); }, "huge", "[0, 4294967295]");
  expect_refused([&] { core::get_field<int>(object, "name", "capture.json"); }, "name", "wrong type");
  EXPECT_EQ(core::get_field<int>(object, "count", "capture.json"), 7);
  EXPECT_EQ(core::get_field<unsigned>(object, "count", "capture.json"), 7u);
  EXPECT_EQ(core::get_field<std::int64_t>(object, "big", "capture.json"), 3000000000);
  EXPECT_EQ(core::get_field<std::uint32_t>(object, "big", "capture.json"), 3000000000u);
  EXPECT_EQ(core::get_field<std::uint64_t>(object, "huge", "capture.json"), 18446744073709551615u);
  EXPECT_EQ(core::get_field<long>(object, "negative", "capture.json"), -1);
  EXPECT_DOUBLE_EQ(core::get_field<double>(object, "count", "capture.json"), 7.0);  // an integer is a number
}

}  // namespace
}  // namespace surfcap
