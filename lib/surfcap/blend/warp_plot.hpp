#pragma once
// PNG plot of the time warps of a motion space: normalised time (x) against source frame (y,
// normalised to each sequence's range), one coloured polyline per sequence.
#include <filesystem>
#include <string>
#include <vector>

namespace surfcap::blend {

/// warps[i][k] as in time_warps(); frame_counts[i] the frames of sequence i. Written atomically.
void write_warp_plot(const std::filesystem::path& path, const std::vector<std::vector<double>>& warps,
                     const std::vector<int>& frame_counts, const std::vector<std::string>& names);

}  // namespace surfcap::blend
