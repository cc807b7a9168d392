#include "surfcap/core/npy.hpp"

#include <bit>
#include <limits>
#include <cstring>
#include <numeric>
#include <regex>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

static_assert(std::endian::native == std::endian::little, "surfcap assumes a little-endian machine");

namespace surfcap::core {
namespace {

constexpr char kMagic[] = "\x93NUMPY";

std::optional<DType> parse_descr(const std::string& descr) {
  static const std::pair<const char*, DType> known[] = {
      {"<f2", DType::float16}, {"<f4", DType::float32}, {"<f8", DType::float64}, {"<i4", DType::int32},
      {"<i8", DType::int64},   {"|u1", DType::uint8},   {"<u1", DType::uint8}};
  for (const auto& [name, type] : known)
    if (descr == name) return type;
  return std::nullopt;
}

std::size_t element_count(const std::vector<std::size_t>& shape) {
  return std::accumulate(shape.begin(), shape.end(), std::size_t{1}, std::multiplies<>());
}

std::string header_dict(const NpyArray& array) {
  std::string shape = "(";
  for (std::size_t i = 0; i < array.shape.size(); ++i) {
    shape += std::to_string(array.shape[i]);
    if (array.shape.size() == 1 || i + 1 < array.shape.size()) shape += ",";
    if (i + 1 < array.shape.size()) shape += " ";
  }
  shape += ")";
  return "{'descr': '" + std::string(dtype_descr(array.dtype)) + "', 'fortran_order': False, 'shape': " + shape +
         ", }";
}

bool matches(const std::vector<std::size_t>& shape, const ShapePattern& pattern) {
  if (shape.size() != pattern.size()) return false;
  for (std::size_t i = 0; i < shape.size(); ++i)
    if (pattern[i] >= 0 && static_cast<std::size_t>(pattern[i]) != shape[i]) return false;
  return true;
}

std::string pattern_string(const ShapePattern& pattern) {
  std::string text = "(";
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    text += pattern[i] < 0 ? std::string("*") : std::to_string(pattern[i]);
    if (i + 1 < pattern.size()) text += ", ";
  }
  return text + ")";
}

}  // namespace

std::string_view dtype_descr(DType type) {
  switch (type) {
    case DType::float16: return "<f2";
    case DType::float32: return "<f4";
    case DType::float64: return "<f8";
    case DType::int32: return "<i4";
    case DType::int64: return "<i8";
    case DType::uint8: return "|u1";
  }
  return "?";
}

std::size_t dtype_size(DType type) {
  switch (type) {
    case DType::float16: return 2;
    case DType::float32: return 4;
    case DType::float64: return 8;
    case DType::int32: return 4;
    case DType::int64: return 8;
    case DType::uint8: return 1;
  }
  return 0;
}

std::size_t NpyArray::size() const { return element_count(shape); }

std::string shape_string(const std::vector<std::size_t>& shape) {
  ShapePattern pattern(shape.begin(), shape.end());
  return pattern_string(pattern);
}

NpyArray read_npy(const std::filesystem::path& path) {
  const std::string content = read_file(path);
  if (content.size() < 10 || content.compare(0, 6, kMagic, 6) != 0)
    throw bad_input(path, "not a .npy file (missing the \\x93NUMPY magic)");
  const int major = static_cast<unsigned char>(content[6]);
  std::size_t header_length = 0, offset = 0;
  if (major == 1) {
    header_length = static_cast<unsigned char>(content[8]) | (static_cast<unsigned char>(content[9]) << 8);
    offset = 10;
  } else if (major == 2 || major == 3) {
    if (content.size() < 12) throw bad_input(path, "truncated .npy header");
    std::uint32_t length = 0;
    std::memcpy(&length, content.data() + 8, 4);
    header_length = length;
    offset = 12;
  } else {
    throw bad_input(path, ".npy format version " + std::to_string(major) + " is not supported");
  }
  if (offset + header_length > content.size()) throw bad_input(path, "truncated .npy header");
  const std::string header = content.substr(offset, header_length);

  static const std::regex descr_re(R"('descr'\s*:\s*'([^']*)')");
  static const std::regex order_re(R"('fortran_order'\s*:\s*(True|False))");
  static const std::regex shape_re(R"('shape'\s*:\s*\(([^)]*)\))");
  std::smatch m;
  if (!std::regex_search(header, m, descr_re)) throw bad_input(path, "npy header has no 'descr'");
  const std::string descr = m[1];
  const auto dtype = parse_descr(descr);
  if (!dtype)
    throw bad_input(path, "npy dtype '" + descr + "' is not supported (expected <f2, <f4, <f8, <i4, <i8 or |u1)");
  if (!std::regex_search(header, m, order_re)) throw bad_input(path, "npy header has no 'fortran_order'");
  if (m[1] == "True") throw bad_input(path, "npy array is in Fortran order; surfcap reads C order only");
  if (!std::regex_search(header, m, shape_re)) throw bad_input(path, "npy header has no 'shape'");

  NpyArray array;
  array.dtype = *dtype;
  const std::string dims = m[1];
  static const std::regex int_re(R"(\d+)");
  const std::size_t data_offset = offset + header_length;
  // Every extent must fit in what the file holds, so the element count cannot overflow.
  const std::size_t available = (content.size() - data_offset) / dtype_size(array.dtype);
  std::size_t elements = 1;
  for (auto it = std::sregex_iterator(dims.begin(), dims.end(), int_re); it != std::sregex_iterator(); ++it) {
    const std::string digits = it->str();
    const std::size_t extent = digits.size() > 15 ? std::numeric_limits<std::size_t>::max() : std::stoull(digits);
    if (extent != 0 && elements != 0 && extent > available / elements)
      throw bad_input(path, "npy data truncated: shape extent " + digits + " exceeds the " +
                                std::to_string(available) + " elements the file holds");
    elements *= extent;
    array.shape.push_back(extent);
  }

  const std::size_t expected = array.size() * dtype_size(array.dtype);
  if (content.size() - data_offset < expected)
    throw bad_input(path, "npy data truncated: shape " + shape_string(array.shape) + " needs " +
                              std::to_string(expected) + " bytes, file has " +
                              std::to_string(content.size() - data_offset));
  const auto* begin = reinterpret_cast<const std::byte*>(content.data() + data_offset);
  array.bytes.assign(begin, begin + expected);
  return array;
}

NpyArray read_npy(const std::filesystem::path& path, DType expected, const ShapePattern& shape) {
  NpyArray array = read_npy(path);
  if (array.dtype != expected)
    throw bad_input(path, "npy dtype is " + std::string(dtype_descr(array.dtype)) + ", expected " +
                              std::string(dtype_descr(expected)));
  if (!matches(array.shape, shape))
    throw bad_input(path, "npy shape is " + shape_string(array.shape) + ", expected " + pattern_string(shape));
  return array;
}

std::vector<double> read_npy_as_double(const std::filesystem::path& path, const ShapePattern& shape,
                                       std::vector<std::size_t>* found_shape) {
  const NpyArray array = read_npy(path);
  if (!matches(array.shape, shape))
    throw bad_input(path, "npy shape is " + shape_string(array.shape) + ", expected " + pattern_string(shape));
  std::vector<double> values(array.size());
  switch (array.dtype) {
    case DType::float16:
      for (std::size_t i = 0; i < values.size(); ++i) values[i] = half_to_float(array.data<std::uint16_t>()[i]);
      break;
    case DType::float32:
      for (std::size_t i = 0; i < values.size(); ++i) values[i] = array.data<float>()[i];
      break;
    case DType::float64:
      if (!values.empty()) std::memcpy(values.data(), array.bytes.data(), array.bytes.size());
      break;
    default:
      throw bad_input(path, "npy dtype is " + std::string(dtype_descr(array.dtype)) + ", expected a float type");
  }
  if (found_shape) *found_shape = array.shape;
  return values;
}

Eigen::MatrixXd read_npy_matrix(const std::filesystem::path& path, long rows, long cols) {
  std::vector<std::size_t> shape;
  const std::vector<double> values = read_npy_as_double(path, {rows, cols}, &shape);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), static_cast<long>(shape[0]), static_cast<long>(shape[1]));
}

void write_npy(const std::filesystem::path& path, const NpyArray& array) {
  if (array.bytes.size() != array.size() * dtype_size(array.dtype))
    throw internal_error("write_npy " + path.string() + ": " + std::to_string(array.bytes.size()) +
                         " bytes do not fill shape " + shape_string(array.shape));
  std::string header = header_dict(array);
  // Version 1.0: magic(6) + version(2) + length(2) + header, padded with spaces to 64 bytes, ending in \n.
  const std::size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header.push_back('\n');
  if (header.size() > 65535) throw internal_error("npy header too long for " + path.string());
  std::string preamble(kMagic, 6);
  preamble.push_back('\x01');
  preamble.push_back('\x00');
  preamble.push_back(static_cast<char>(header.size() & 0xff));
  preamble.push_back(static_cast<char>(header.size() >> 8));
  AtomicFile file(path);
  file.write(preamble);
  file.write(header);
  file.write(array.bytes.data(), array.bytes.size());
  file.commit();
}

std::uint16_t float_to_half(float value) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
  const std::uint32_t sign = (bits >> 16) & 0x8000u;
  const std::uint32_t abs = bits & 0x7fffffffu;
  if (abs >= 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u));
  if (abs >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // overflow to infinity
  if (abs < 0x38800000u) {                                                     // subnormal or zero
    if (abs < 0x33000000u) return static_cast<std::uint16_t>(sign);
    const std::uint32_t mantissa = (abs & 0x7fffffu) | 0x800000u;
    const int shift = 113 - static_cast<int>(abs >> 23) + 13;
    std::uint32_t half = mantissa >> shift;
    const std::uint32_t rest = mantissa & ((1u << shift) - 1);
    const std::uint32_t halfway = 1u << (shift - 1);
    if (rest > halfway || (rest == halfway && (half & 1u))) ++half;
    return static_cast<std::uint16_t>(sign | half);
  }
  std::uint32_t half = ((abs - 0x38000000u) >> 13);
  const std::uint32_t rest = abs & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (half & 1u))) ++half;
  return static_cast<std::uint16_t>(sign | half);
}

float half_to_float(std::uint16_t half) {
  const std::uint32_t sign = (half & 0x8000u) << 16;
  const std::uint32_t exponent = (half >> 10) & 0x1fu;
  std::uint32_t mantissa = half & 0x3ffu;
  std::uint32_t bits;
  if (exponent == 0) {
    if (mantissa == 0) {
      bits = sign;
    } else {  // subnormal: normalise
      int e = -1;
      do {
        ++e;
        mantissa <<= 1;
      } while ((mantissa & 0x400u) == 0);
      bits = sign | ((112 - e) << 23) | ((mantissa & 0x3ffu) << 13);
    }
  } else if (exponent == 31) {
    bits = sign | 0x7f800000u | (mantissa << 13);
  } else {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  }
  return std::bit_cast<float>(bits);
}

}  // namespace surfcap::core
