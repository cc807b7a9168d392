#include "surfcap/learn/example_selection.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include "surfcap/core/error.hpp"

namespace surfcap::learn {

std::vector<ExampleFrame> all_frames(const core::AlignedDatabase& database) { return strided_frames(database, 1); }

std::vector<ExampleFrame> strided_frames(const core::AlignedDatabase& database, int stride) {
  if (stride < 1) throw core::bad_arguments("frame stride must be ≥ 1");
  std::vector<ExampleFrame> frames;
  for (std::size_t s = 0; s < database.sequences.size(); ++s)
    for (int f = 0; f < database.sequences[s].frame_count(); f += stride)
      frames.push_back({static_cast<int>(s), f});
  return frames;
}

std::vector<ExampleFrame> farthest_pose_frames(const core::AlignedDatabase& database, int count,
                                               const std::vector<ExampleFrame>& given) {
  const std::vector<ExampleFrame> candidates = given.empty() ? all_frames(database) : given;
  if (count <= 0) throw core::bad_arguments("--examples must be ≥ 1");
  if (static_cast<std::size_t>(count) >= candidates.size()) return candidates;
  auto pose = [&](const ExampleFrame& e) -> const Eigen::MatrixXd& {
    return database.sequences[e.sequence].frames[e.frame];
  };
  std::size_t first = 0;
  const int root_sequence = database.sequence_index(database.root_sequence);
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].sequence == root_sequence && candidates[i].frame == database.root_frame) first = i;
  std::vector<double> nearest(candidates.size(), std::numeric_limits<double>::infinity());
  std::vector<std::size_t> chosen;
  std::size_t next = first;
  for (int k = 0; k < count; ++k) {
    chosen.push_back(next);
    const Eigen::MatrixXd& p = pose(candidates[next]);
    double far = -1;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      nearest[i] = std::min(nearest[i], (pose(candidates[i]) - p).squaredNorm());
      if (nearest[i] > far) far = nearest[i], next = i;  // first index wins ties: deterministic
    }
  }
  std::sort(chosen.begin(), chosen.end());
  std::vector<ExampleFrame> frames;
  for (std::size_t i : chosen) frames.push_back(candidates[i]);
  return frames;
}

std::vector<ExampleFrame> parse_frame_list(const core::AlignedDatabase& database, const std::string& list) {
  std::vector<ExampleFrame> frames;
  std::stringstream stream(list);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const auto colon = item.rfind(':');
    if (colon == std::string::npos) throw core::bad_arguments("frame list item '" + item + "' is not sequence:frame");
    const int s = database.sequence_index(item.substr(0, colon));
    if (s < 0) throw core::bad_arguments("frame list: unknown sequence in '" + item + "'");
    int f = -1;
    try {
      f = std::stoi(item.substr(colon + 1));
    } catch (const std::exception&) {
      throw core::bad_arguments("frame list: bad frame number in '" + item + "'");
    }
    if (f < 0 || f >= database.sequences[s].frame_count())
      throw core::bad_arguments("frame list: frame out of range in '" + item + "'");
    frames.push_back({s, f});
  }
  if (frames.empty()) throw core::bad_arguments("empty frame list");
  return frames;
}

}  // namespace surfcap::learn
