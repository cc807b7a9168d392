#pragma once
// The shape-similarity steps of surfcap-align as library stages (docs/cli.md): each reads and
// writes the database folder's similarity/ files and writes its report; `surfcap-align run`
// chains the same calls.

#include <filesystem>
#include <optional>
#include <string>

#include "surfcap/core/json_document.hpp"
#include "surfcap/similarity/shape_histogram.hpp"
#include "surfcap/similarity/similarity_matrix.hpp"

namespace surfcap::similarity {

/// The options of the steps, as their commands take them.
struct SimilarityStageOptions {
  ShapeHistogramOptions histogram;
  SimilarityOptions similarity;  ///< threads are set from `threads`
  std::string rows;              ///< "a:b": one row block of the matrix (empty: all)
  std::string search = "fft";    ///< rotation search: "fft" or "exhaustive"
  std::string root;              ///< "<sequence>:<frame>" (empty: automatic)
  double root_candidates = 0.25;
  std::string ground_truth;      ///< a true database.json: the tree's quality ratio (empty: none)
  int threads = 0;
  core::Json options_json;       ///< the command's options, copied into the reports
};

/// capture → similarity/histograms.{npy,json}, report/histograms.json.
void run_histograms_stage(const std::filesystem::path& capture, const std::filesystem::path& out,
                          const SimilarityStageOptions& options);

/// histograms → similarity/matrix.{npy,png} (or a row block into similarity/rows/), its report.
void run_similarity_stage(const std::filesystem::path& out, const SimilarityStageOptions& options);

/// similarity/rows/*.npy → similarity/matrix.{npy,png}.
void run_merge_stage(const std::filesystem::path& out);

/// matrix → similarity/tree.{json,png}, report/similarity.json.
void run_tree_stage(const std::filesystem::path& out, const SimilarityStageOptions& options);

/// histograms → similarity → tree on the whole matrix, as the three commands do in turn.
void run_similarity_chain(const std::filesystem::path& capture, const std::filesystem::path& out,
                          const SimilarityStageOptions& options);

}  // namespace surfcap::similarity
