#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using core::DType;
using testing::TemporaryDirectory;

TEST(Npy, Float32RoundTripKeepsShapeAndValues) {
  TemporaryDirectory dir("npy_f32");
  std::vector<float> values(2 * 3 * 4);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.5f * static_cast<float>(i) - 3.25f;
  core::write_npy(dir / "a.npy", values.data(), {2, 3, 4});
  const core::NpyArray back = core::read_npy(dir / "a.npy", DType::float32, {2, 3, 4});
  ASSERT_EQ(back.shape, (std::vector<std::size_t>{2, 3, 4}));
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(back.data<float>()[i], values[i]);
}

TEST(Npy, HeaderIsNumpyCompatible) {
  TemporaryDirectory dir("npy_header");
  const std::int32_t values[] = {1, 2, 3};
  core::write_npy(dir / "i.npy", values, {3});
  const std::string bytes = core::read_file(dir / "i.npy");
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_length = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
  EXPECT_EQ((10 + header_length) % 64, 0u);  // data aligned as numpy does
  const std::string header = bytes.substr(10, header_length);
  EXPECT_EQ(header.rfind("{'descr': '<i4', 'fortran_order': False, 'shape': (3,), }", 0), 0u) << header;
  EXPECT_EQ(header.back(), '\n');
  EXPECT_EQ(bytes.size(), 10 + header_length + 12);
}

TEST(Npy, Float64AndInt32RoundTrip) {
  TemporaryDirectory dir("npy_types");
  const double d[] = {1e-300, -2.5, std::numeric_limits<double>::max()};
  core::write_npy(dir / "d.npy", d, {3, 1});
  const auto back = core::read_npy(dir / "d.npy", DType::float64, {3, 1});
  EXPECT_EQ(back.data<double>()[0], d[0]);
  EXPECT_EQ(back.data<double>()[2], d[2]);
  const std::int32_t i[] = {-7, 0, 2147483647, 5};
  core::write_npy(dir / "i.npy", i, {2, 2});
  EXPECT_EQ(core::read_npy(dir / "i.npy", DType::int32, {2, 2}).data<std::int32_t>()[2], 2147483647);
}

TEST(Npy, MatrixHelpersConvert) {
  TemporaryDirectory dir("npy_matrix");
  Eigen::MatrixXd m(2, 3);
  m << 1, 2, 3, 4, 5, 6;
  core::write_npy_matrix<float>(dir / "m.npy", m);
  EXPECT_EQ(core::read_npy_matrix(dir / "m.npy", 2, 3), m);  // row-major order preserved
  EXPECT_THROW(core::read_npy_matrix(dir / "m.npy", 3, -1), core::Error);
}

TEST(Npy, WrongDtypeNamesFileAndTypes) {
  TemporaryDirectory dir("npy_dtype");
  const float f[] = {1, 2};
  core::write_npy(dir / "f.npy", f, {2});
  try {
    core::read_npy(dir / "f.npy", DType::int32, {2});
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(e.what()).find("f.npy"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("<f4"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("<i4"), std::string::npos);
  }
}

TEST(Npy, WrongShapeIsBadInput) {
  TemporaryDirectory dir("npy_shape");
  const float f[] = {1, 2, 3, 4, 5, 6};
  core::write_npy(dir / "f.npy", f, {2, 3});
  EXPECT_NO_THROW(core::read_npy(dir / "f.npy", DType::float32, {-1, 3}));
  try {
    core::read_npy(dir / "f.npy", DType::float32, {-1, 4});
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(e.what()).find("(2, 3)"), std::string::npos) << e.what();
  }
}

TEST(Npy, TruncatedAndCorruptFilesAreBadInput) {
  TemporaryDirectory dir("npy_bad");
  const float f[] = {1, 2, 3, 4};
  core::write_npy(dir / "f.npy", f, {4});
  const std::string bytes = core::read_file(dir / "f.npy");
  testing::write_text(dir / "cut.npy", bytes.substr(0, bytes.size() - 3));
  testing::write_text(dir / "junk.npy", "hello world, not numpy");
  std::string fortran = bytes;
  fortran.replace(fortran.find("False"), 5, "True ");
  testing::write_text(dir / "fortran.npy", fortran);
  std::string big_endian = bytes;
  big_endian.replace(big_endian.find("<f4"), 3, ">f4");
  testing::write_text(dir / "big.npy", big_endian);
  for (const char* name : {"cut.npy", "junk.npy", "fortran.npy", "big.npy"}) {
    try {
      core::read_npy(dir / name);
      FAIL() << name;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ExitCode::bad_input) << e.what();
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  try {
    core::read_npy(dir / "absent.npy");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ExitCode::io);
  }
}

TEST(Npy, HalfConversionRoundTripsEveryHalf) {
  for (std::uint32_t bits = 0; bits < 0x10000u; ++bits) {
    const auto half = static_cast<std::uint16_t>(bits);
    const float value = core::half_to_float(half);
    if (std::isnan(value)) {
      EXPECT_TRUE(std::isnan(core::half_to_float(core::float_to_half(value))));
      continue;
    }
    ASSERT_EQ(core::float_to_half(value), half) << "half 0x" << std::hex << bits << " = " << value;
  }
  EXPECT_EQ(core::half_to_float(core::float_to_half(1.0f)), 1.0f);
  EXPECT_EQ(core::half_to_float(core::float_to_half(65504.0f)), 65504.0f);
  EXPECT_TRUE(std::isinf(core::half_to_float(core::float_to_half(1e6f))));
  EXPECT_NEAR(core::half_to_float(core::float_to_half(0.1f)), 0.1f, 0.1f / 1024);
}

}  // namespace
}  // namespace surfcap
