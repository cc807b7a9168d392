#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/option_table.hpp"

namespace surfcap::align {
namespace {

/// The JSON leaves of `json` as dotted paths.
void leaves(const core::Json& json, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& [key, value] : json.items()) {
    if (value.is_object())
      leaves(value, prefix + key + ".", out);
    else
      out.push_back(prefix + key);
  }
}

std::string flag_of(const std::string& path) {
  std::string flag = "--" + path;
  for (char& c : flag)
    if (c == '.' || c == '_') c = '-';
  return flag;
}

TEST(AlignmentOptions, TableJsonAndCommandLineAgree) {
  RegisterOptions options;
  const std::vector<std::string> paths = core::option_paths(options);
  std::vector<std::string> json_paths;
  leaves(options.to_json(), "", json_paths);
  std::vector<std::string> sorted = paths;
  std::sort(sorted.begin(), sorted.end());
  std::sort(json_paths.begin(), json_paths.end());
  EXPECT_EQ(sorted, json_paths);  // every table entry in the provenance, nothing else
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a name is declared twice";
  for (const char* output_affecting : {"uncovered_distance_edges", "patches", "crease.weight", "flow.weight",
                                       "feature.ratio", "failure_residual_mm", "twin_prediction", "surface_model"})
    EXPECT_NE(std::find(paths.begin(), paths.end(), output_affecting), paths.end()) << output_affecting;

  CLI::App app;
  core::add_options(&app, options);
  std::vector<std::string> flags;
  for (const CLI::Option* option : app.get_options())
    if (!option->get_lnames().empty()) flags.push_back("--" + option->get_lnames().front());
  for (const std::string& path : paths)
    EXPECT_NE(std::find(flags.begin(), flags.end(), flag_of(path)), flags.end()) << "no flag for " << path;
}

TEST(AlignmentOptions, FlagsSetTheFieldsTheJsonReports) {
  RegisterOptions options;
  CLI::App app;
  core::add_options(&app, options);
  app.parse(std::vector<std::string>{"1.7", "--uncovered-distance-edges", "off", "--crease-weight", "12",
                                     "--patches", "0.5", "--feature-ratio", "--no-images"});
  EXPECT_EQ(options.pairwise.patches, 12);
  EXPECT_FALSE(options.pairwise.crease.weight.has_value());
  EXPECT_DOUBLE_EQ(options.pairwise.checks.uncovered_distance_edges, 1.7);
  EXPECT_DOUBLE_EQ(options.pairwise.feature.ratio, 0.5);
  EXPECT_FALSE(options.images);
  const core::Json json = options.to_json();
  EXPECT_TRUE(json.at("crease").at("weight").is_null());
  EXPECT_EQ(json.at("patches").get<int>(), 12);
  EXPECT_DOUBLE_EQ(json.at("uncovered_distance_edges").get<double>(), 1.7);
  EXPECT_FALSE(json.at("images").get<bool>());
}

TEST(AlignmentOptions, OutOfRangeValuesAreRejectedNamingTheFlag) {
  {
    RegisterOptions options;
    CLI::App app;
    core::add_options(&app, options);
    EXPECT_THROW(app.parse(std::vector<std::string>{"0", "--patches"}), CLI::ValidationError);
  }
  {
    RegisterOptions options;
    CLI::App app;
    core::add_options(&app, options);
    EXPECT_THROW(app.parse(std::vector<std::string>{"-1", "--flow-weight"}), CLI::ValidationError);
  }
  RegisterOptions options;
  options.pairwise.crease.angle_deg = 180;
  try {
    options.validate();
    FAIL() << "accepted a crease angle of 180 degrees";
  } catch (const core::Error& error) {
    EXPECT_NE(std::string(error.what()).find("--crease-angle-deg"), std::string::npos) << error.what();
  }
  options = RegisterOptions{};
  EXPECT_NO_THROW(options.validate());
}

}  // namespace
}  // namespace surfcap::align
