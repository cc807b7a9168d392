#include "import_command.hpp"

#include <spdlog/spdlog.h>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/io/camera_import.hpp"
#include "surfcap/io/camera_preview.hpp"
#include "surfcap/io/capture_import.hpp"

namespace surfcap::tools {

struct ImportCommands::State {
  CLI::App* cameras_cmd = nullptr;
  CLI::App* capture_cmd = nullptr;
  std::string colmap;
  std::vector<std::string> opencv;
  std::string out;
  double scale = 1.0;
  io::CaptureImportOptions capture;
  std::string calibration;
  bool force = false;
};

namespace {

core::Json cameras_json(const std::vector<core::CaptureCamera>& cameras) {
  core::Json list = core::Json::array();
  for (const auto& camera : cameras) {
    const Eigen::Vector3d centre = -camera.R.transpose() * camera.t;
    list.push_back({{"name", camera.name}, {"width", camera.width}, {"height", camera.height},
                    {"focal_px", {camera.K(0, 0), camera.K(1, 1)}}, {"centre_m", {centre.x(), centre.y(), centre.z()}},
                    {"distorted", !camera.distortion.isZero()}});
  }
  return list;
}

void import_cameras(const ImportCommands::State& s) {
  core::StageReport report("align.import_cameras");
  if (s.colmap.empty() == s.opencv.empty())
    throw core::bad_arguments("import-cameras needs either --colmap FOLDER or --opencv FILE...");
  std::vector<core::CaptureCamera> cameras;
  core::Json sources = core::Json::array();
  if (!s.colmap.empty()) {
    cameras = io::read_colmap_cameras(s.colmap);
    sources.push_back({{"colmap", s.colmap}});
  }
  for (const auto& file : s.opencv) {
    for (auto& camera : io::read_opencv_cameras(file)) cameras.push_back(camera);
    sources.push_back({{"opencv", file}});
  }
  io::scale_translations(cameras, s.scale);
  io::check_cameras(cameras, s.opencv.empty() ? s.colmap : s.opencv.back());
  core::write_cameras(s.out, cameras);
  const std::filesystem::path out(s.out);
  report.figures()["cameras"] = cameras_json(cameras);
  report.figures()["sources"] = sources;
  report.figures()["scale"] = s.scale;
  report.figures()["output"] = s.out;
  render::write_png(out.parent_path() / "report" / "import-cameras.png", io::camera_layout_preview(cameras));
  report.write(out.parent_path() / "report" / "import-cameras.json");
  spdlog::info("{} cameras → {}", cameras.size(), s.out);
}

void import_capture(const ImportCommands::State& s) {
  core::StageReport report("align.import_capture");
  io::CaptureImportOptions options = s.capture;
  options.calibration = s.calibration;
  const auto target = options.folder / "capture.json";
  if (std::filesystem::exists(target) && !s.force)
    throw core::bad_arguments("'" + target.string() + "' exists (--force replaces it)");
  core::Capture capture = io::import_capture(options);
  core::write_capture(capture);
  capture = core::read_capture(target);  // what the stages will read
  core::Json sequences = core::Json::array();
  for (const auto& sequence : capture.sequences)
    sequences.push_back({{"name", sequence.name}, {"frames", sequence.frames}, {"first", sequence.first},
                         {"count", sequence.count}, {"images", sequence.images}});
  report.figures()["sequences"] = sequences;
  report.figures()["frames"] = capture.total_frames();
  report.figures()["cameras"] = cameras_json(capture.cameras);
  report.figures()["calibration"] = s.calibration;
  if (!capture.cameras.empty())
    render::write_png(options.folder / "report" / "import-capture.png", io::camera_layout_preview(capture.cameras));
  report.write(options.folder / "report" / "import-capture.json");
  spdlog::info("{} sequences, {} frames, {} cameras → {}", capture.sequences.size(), capture.total_frames(),
               capture.cameras.size(), target.string());
}

}  // namespace

ImportCommands::ImportCommands(core::ToolApp& app) : app_(app), state_(std::make_unique<State>()) {
  auto& cli = app.cli();
  State& s = *state_;
  s.cameras_cmd = cli.add_subcommand("import-cameras", "COLMAP or OpenCV calibrations → cameras.json");
  s.cameras_cmd->add_option("--colmap", s.colmap, "COLMAP text model folder (cameras.txt + images.txt)");
  s.cameras_cmd->add_option("--opencv", s.opencv, "OpenCV FileStorage calibration files (.yml .yaml .xml)");
  s.cameras_cmd->add_option("--out", s.out, "cameras.json to write")->required();
  s.cameras_cmd->add_option("--scale", s.scale, "Calibration translation units → metres (1000 mm → 0.001)");

  s.capture_cmd = cli.add_subcommand("import-capture", "A folder of numbered reconstructions → capture.json");
  s.capture_cmd->add_option("--folder", s.capture.folder, "Capture folder: one subfolder of numbered meshes per sequence")
      ->required();
  s.capture_cmd->add_option("--calibration", s.calibration,
                            "cameras.json, COLMAP text model folder or OpenCV .yml/.yaml/.xml (default: "
                            "FOLDER/cameras.json if present)");
  s.capture_cmd->add_option("--scale", s.capture.scale, "Calibration translation units → metres");
  s.capture_cmd->add_option("--fps", s.capture.fps, "Frame rate");
  s.capture_cmd->add_option("--name", s.capture.name, "Capture name (default: the folder's name)");
  s.capture_cmd->add_option("--mesh-format", s.capture.mesh_format, "ply, obj or off, where a folder holds several series")
      ->check(CLI::IsMember({"ply", "obj", "off"}));
  s.capture_cmd->add_flag("--force", s.force, "Replace an existing capture.json");
}

ImportCommands::~ImportCommands() = default;

void ImportCommands::run() const {
  if (*state_->cameras_cmd) import_cameras(*state_);
  if (*state_->capture_cmd) import_capture(*state_);
}

}  // namespace surfcap::tools
