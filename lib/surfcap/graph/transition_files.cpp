#include "surfcap/graph/transition_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/render/colormap.hpp"
#include "surfcap/render/png.hpp"

namespace surfcap::graph {
namespace {

/// Heat map of 1 − s (blue similar → red dissimilar), at least 512 pixels on the long side, with
/// white lines between the reference sequences (grid nodes) of each space.
void write_transition_png(const std::filesystem::path& path, const TransitionSimilarity& similarity, int from_frames,
                          int to_frames) {
  Eigen::MatrixXd dissimilarity(similarity.rows, similarity.cols);
  for (long i = 0; i < similarity.rows; ++i)
    for (long j = 0; j < similarity.cols; ++j)
      dissimilarity(i, j) = 1.0 - similarity.similarity[static_cast<std::size_t>(i * similarity.cols + j)];
  const long longest = std::max(similarity.rows, similarity.cols);
  const int cell = static_cast<int>(std::max<long>(1, (512 + longest - 1) / longest));
  render::Image image = render::matrix_image(dissimilarity, 0.0, 1.0, cell);
  const Eigen::Vector3d white(1, 1, 1);
  for (long row = from_frames; row < similarity.rows; row += from_frames)
    for (int x = 0; x < image.width; ++x) image.set(x, static_cast<int>(row * cell), white);
  for (long col = to_frames; col < similarity.cols; col += to_frames)
    for (int y = 0; y < image.height; ++y) image.set(static_cast<int>(col * cell), y, white);
  render::write_png(path, image);
}

}  // namespace

std::string transition_stem(const std::string& from, const std::string& to) { return from + "__" + to; }

void write_transition(const std::filesystem::path& output, const blend::StoredSpace& from,
                      const blend::StoredSpace& to, const TransitionSimilarity& similarity,
                      const core::Json& provenance) {
  const std::string stem = transition_stem(from.name, to.name);
  const std::filesystem::path directory = output / "transitions";
  core::write_npy(directory / (stem + ".npy"), similarity.similarity.data(),
                  {static_cast<std::size_t>(similarity.rows), static_cast<std::size_t>(similarity.cols)});
  write_transition_png(directory / (stem + ".png"), similarity, from.frames, to.frames);
  const core::Json metadata = {{"format", core::format_tag("transition", 1)},
                               {"from", from.name},
                               {"to", to.name},
                               {"rows", similarity.rows},
                               {"cols", similarity.cols},
                               {"from_nodes", from.node_count()},
                               {"from_frames", from.frames},
                               {"to_nodes", to.node_count()},
                               {"to_frames", to.frames},
                               {"velocity_weight", similarity.figures.value("velocity_weight", 1.0)},
                               {"max_distance_m2", similarity.max_distance},
                               {"similarity", "transitions/" + stem + ".npy"},
                               {"preview", "transitions/" + stem + ".png"},
                               {"provenance", provenance}};
  core::write_json_file(directory / (stem + ".json"), metadata);
}

std::vector<float> read_transition_similarity(const std::filesystem::path& output, const std::string& from,
                                              const std::string& to, long rows, long cols) {
  const std::filesystem::path path = output / "transitions" / (transition_stem(from, to) + ".npy");
  if (!std::filesystem::exists(path))
    throw core::bad_input(path, "missing (a declared transition): run `surfcap-precompute transitions --edge " + from + ":" + to + "`");
  const core::NpyArray array = core::read_npy(path, core::DType::float32, {rows, cols});
  std::vector<float> values(array.size());
  if (!values.empty()) std::memcpy(values.data(), array.bytes.data(), values.size() * sizeof(float));
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!(values[k] >= 0.0f && values[k] <= 1.0f))
      throw core::bad_input(path, "similarity " + std::to_string(values[k]) + " outside [0, 1] at row " +
                                      std::to_string(static_cast<long>(k) / cols));
  return values;
}

}  // namespace surfcap::graph
