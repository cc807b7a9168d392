#pragma once
// Which frames of an aligned database the models learn from (tejera2013 §V: extreme poses
// enrich the space, so farthest-point sampling keeps rare poses).
#include <string>
#include <vector>

#include "surfcap/core/database.hpp"

namespace surfcap::learn {

struct ExampleFrame {
  int sequence = 0;  ///< index into AlignedDatabase::sequences
  int frame = 0;
  bool operator==(const ExampleFrame&) const = default;
};

/// Every frame of every sequence, in order.
std::vector<ExampleFrame> all_frames(const core::AlignedDatabase& database);

/// Every `stride`-th frame of every sequence (starting at frame 0).
std::vector<ExampleFrame> strided_frames(const core::AlignedDatabase& database, int stride);

/// `count` frames by farthest-point sampling in pose space (RMS vertex distance of centred
/// frames), starting from the root frame; returned in database order. count ≥ total: all.
std::vector<ExampleFrame> farthest_pose_frames(const core::AlignedDatabase& database, int count,
                                               const std::vector<ExampleFrame>& candidates = {});

/// "walk:0,walk:4,run:10" → frames (bad_arguments naming the item on error).
std::vector<ExampleFrame> parse_frame_list(const core::AlignedDatabase& database, const std::string& list);

}  // namespace surfcap::learn
