#pragma once
// What surfcap-align register reports (docs/align.md): per-frame figures for
// report/alignment.json and a PNG heat map of the residual (aligned surface → reconstruction).

#include <filesystem>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::evaluation {

/// {"frames":[{"sequence","frame","node","parent","depth","mean_residual_m","max_residual_m",
/// "correspondences":{"patch","dense","feature",...},"accepted_patches","color_patches","total_patches",
/// "heading_change_rad","seconds","timings_s":{matching,factorisation,solves}}], "summary":{...}}
core::Json alignment_figures(const align::Registration& registration);

/// Nodes worth showing: the root, the deepest frame, the frame with the largest residual and one
/// in between (distinct, at most `count`, in node order).
std::vector<long> preview_nodes(const align::Registration& registration, int count = 4);

/// Renders the aligned template of each node (front view, orthographic, flat shaded) coloured by
/// the distance of each vertex to that frame's reconstruction (blue 0 → red `scale` metres), side
/// by side, and writes the PNG atomically.
void write_residual_preview(const std::filesystem::path& path, const core::Capture& capture,
                            const align::Registration& registration, const std::vector<long>& nodes, double scale);

/// Is there anything for the observation preview: a closing surface, template vertices no root
/// camera sees, a volume cut between touching parts, a frame with open holes or with merged regions?
bool has_observation_figures(const align::Registration& registration);

/// The aligned template of each node, front and side, coloured by observation: blue where the
/// vertex is the reconstruction's and its closest point on the frame's reconstruction is observed,
/// orange where that point lies on a hole's rim (align/observed_surface.hpp), red on the closing
/// surface of the template, green in a region the reconstruction merged with another part
/// (align/pairwise_checks.hpp), yellow where the template's volume was cut between parts that touch
/// at the root (align/volume_deformer.hpp), cyan where no camera sees the template at the root (and
/// its volume is soft: align/alignment_template.hpp); the labels give the frame's holes, unobserved fraction
/// and merged regions. The root is also drawn from below, where most of what no camera sees is.
void write_observation_preview(const std::filesystem::path& path, const core::Capture& capture,
                               const align::Registration& registration, const std::vector<long>& nodes);

/// The same panels coloured by given per-vertex values (e.g. the error against ground truth),
/// front and side views of each node; `what` labels the colour bar.
void write_value_preview(const std::filesystem::path& path, const align::Registration& registration,
                         const std::vector<long>& nodes, const std::vector<Eigen::VectorXd>& values, double scale,
                         const std::string& what);

}  // namespace surfcap::evaluation
