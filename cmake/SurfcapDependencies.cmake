# Every dependency comes from Debian's packages (scripts/setup.sh installs them).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
# CONFIG: CGAL ships a FindOpenMesh module that shadows OpenMesh's own config.
find_package(OpenMesh REQUIRED CONFIG)
find_package(spdlog REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(OpenMP REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs features2d calib3d video)
# flann's pkg-config file asks for -lhdf5; its CMake config does not.
find_package(flann REQUIRED CONFIG)
find_package(CGAL REQUIRED)
find_path(TETGEN_INCLUDE_DIR tetgen.h REQUIRED)
find_library(TETGEN_LIBRARY tet REQUIRED)
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
# EXT_meshopt_compression of character.glb (asset/glb_model.cpp, asset/glb_meshopt.cpp) and its
# vertex order (asset/vertex_order.cpp).
# The library itself, not its CMake target: the target defines MESHOPTIMIZER_API for every file.
find_path(MESHOPTIMIZER_INCLUDE_DIR meshoptimizer.h REQUIRED)
find_library(MESHOPTIMIZER_LIBRARY meshoptimizer REQUIRED)
