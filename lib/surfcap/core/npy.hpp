#pragma once
// NumPy .npy arrays (format 1.0/2.0 read, 1.0 written), little-endian, C order, so users can
// open every array of surfcap in Python. Supported dtypes: <f2 <f4 <f8 <i4 <i8 |u1.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace surfcap::core {

enum class DType { float16, float32, float64, int32, int64, uint8 };

std::string_view dtype_descr(DType type);    ///< "<f4" ...
std::size_t dtype_size(DType type);

template <class T> constexpr DType dtype_of();
template <> constexpr DType dtype_of<float>() { return DType::float32; }
template <> constexpr DType dtype_of<double>() { return DType::float64; }
template <> constexpr DType dtype_of<std::int32_t>() { return DType::int32; }
template <> constexpr DType dtype_of<std::int64_t>() { return DType::int64; }
template <> constexpr DType dtype_of<std::uint8_t>() { return DType::uint8; }

/// An untyped array as stored: dtype, shape and raw little-endian bytes in C order.
struct NpyArray {
  DType dtype = DType::float32;
  std::vector<std::size_t> shape;
  std::vector<std::byte> bytes;

  std::size_t size() const;  ///< number of elements
  template <class T> const T* data() const { return reinterpret_cast<const T*>(bytes.data()); }
  template <class T> T* data() { return reinterpret_cast<T*>(bytes.data()); }
};

/// Shape with wildcards: -1 matches any extent.
using ShapePattern = std::vector<long>;

std::string shape_string(const std::vector<std::size_t>& shape);

/// Reads any supported .npy; bad_input (3) for a malformed header, unsupported dtype, Fortran
/// order, big-endian data or a file shorter than its shape; io_error (4) when unreadable.
NpyArray read_npy(const std::filesystem::path& path);
/// Same, and checks dtype and shape: bad_input naming the file, expected and found.
NpyArray read_npy(const std::filesystem::path& path, DType expected, const ShapePattern& shape);
/// Reads a float16/32/64 array of any shape as doubles (dtype conversion allowed), shape checked.
std::vector<double> read_npy_as_double(const std::filesystem::path& path, const ShapePattern& shape,
                                       std::vector<std::size_t>* found_shape = nullptr);

/// Writes atomically. `bytes` must hold exactly prod(shape) elements of `dtype`.
void write_npy(const std::filesystem::path& path, const NpyArray& array);
template <class T>
void write_npy(const std::filesystem::path& path, const T* values, const std::vector<std::size_t>& shape) {
  NpyArray array;
  array.dtype = dtype_of<T>();
  array.shape = shape;
  const auto* begin = reinterpret_cast<const std::byte*>(values);
  array.bytes.assign(begin, begin + array.size() * sizeof(T));
  write_npy(path, array);
}

/// A row-major n×k Eigen matrix as a 2-D array of the given element type (converted).
template <class T, class Derived>
void write_npy_matrix(const std::filesystem::path& path, const Eigen::MatrixBase<Derived>& matrix) {
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = matrix.template cast<T>();
  write_npy(path, rows.data(), {static_cast<std::size_t>(rows.rows()), static_cast<std::size_t>(rows.cols())});
}

/// A 2-D float array (float16/32/64 converted) as an Eigen double matrix; `cols` < 0 means any.
Eigen::MatrixXd read_npy_matrix(const std::filesystem::path& path, long rows = -1, long cols = -1);

/// IEEE half conversions (round to nearest even), for quantised storage.
std::uint16_t float_to_half(float value);
float half_to_float(std::uint16_t half);

}  // namespace surfcap::core
