#pragma once
// Files of the similarity stage (docs/formats.md, "Similarity"): histograms, matrix row blocks,
// the merged matrix and the shape similarity tree, all under <database>/similarity/.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/surface_topology.hpp"
#include "surfcap/similarity/shape_histogram.hpp"
#include "surfcap/similarity/similarity_matrix.hpp"
#include "surfcap/similarity/spanning_tree.hpp"

namespace surfcap::similarity {

using FloatRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Which capture frames the N rows stand for, in order: every sequence's frames first..first+count-1.
struct FrameList {
  struct Sequence {
    std::string name;
    int first = 0;
    int count = 0;
  };
  std::vector<Sequence> sequences;

  FrameIndex index() const;
  /// "walk:12" for node i (frame number, not offset).
  std::string label(long node) const;
  /// Node of "sequence:frame"; bad_arguments if there is none.
  long node(const std::string& label) const;
};

/// One frame's reconstruction as the histograms saw it (after repair): holes left open, pieces,
/// genus. Reported in report/histograms.json, not stored in histograms.json.
struct FrameSurface {
  long vertices = 0;
  long faces = 0;
  long holes_filled = 0;  ///< small holes the repair closed
  core::SurfaceTopology topology;
};

struct HistogramSet {
  FrameList frames;
  ShapeHistogramOptions options;
  FloatRows histograms;  ///< N×B
  std::string capture;   ///< the capture folder it came from (provenance)
  /// Per frame, stance_width of its mesh (the automatic template choice); empty when read from a
  /// histograms.json without a `stance` field.
  std::vector<double> stance;
  /// Per frame, from compute_histograms only (empty when read from disk).
  std::vector<FrameSurface> surfaces;
};

/// How far apart the feet are, as a fraction of the height: the extent of the lowest 15 % of the
/// mesh's vertices (by height, +y up) along their principal horizontal axis, over the mesh's
/// height. A stride or a straddle is wide; legs together, a crouch or a jump's tuck are narrow.
double stance_width(const core::Mesh& mesh);

/// Histograms of every frame of a capture, in parallel. Each frame's mesh is read and checked
/// (non-manifold edges and small defects are tolerated with a warning; the volume sampling copes);
/// open surfaces (any hole size), several pieces and any genus are accepted and described in
/// `surfaces`; errors (corrupt data) name the file and frame.
HistogramSet compute_histograms(const core::Capture& capture, const ShapeHistogramOptions& options, int threads,
                                const core::ProgressCallback& progress = {});

/// The per-frame surfaces for report/histograms.json: counts of open, multi-piece and non-zero
/// genus frames, genus changes between consecutive frames, and one entry per frame.
core::Json surfaces_report(const HistogramSet& set);

/// similarity/histograms.npy (float32 [N, B]) + similarity/histograms.json.
void write_histograms(const std::filesystem::path& database, const HistogramSet& set);
HistogramSet read_histograms(const std::filesystem::path& database);

/// "a:b" → [a, b); bad_arguments if malformed or outside 0..n.
std::pair<long, long> parse_row_range(const std::string& text, long n);
std::filesystem::path row_block_path(const std::filesystem::path& database, long begin, long end);
/// Joins similarity/rows/*.npy, which must tile 0..N exactly (bad_input names the gap or overlap).
FloatRows merge_row_blocks(const std::filesystem::path& database, long n);

std::filesystem::path matrix_path(const std::filesystem::path& database);
FloatRows read_matrix(const std::filesystem::path& database, long n);

/// similarity/tree.json (format surfcap.tree/1).
void write_tree(const std::filesystem::path& database, const SimilarityTree& tree, const FrameList& frames);

}  // namespace surfcap::similarity
