// libFuzzer target: core::read_npy on arbitrary bytes.
#include "fuzz_support.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = surfcap::fuzz::scratch_file(data, size, ".npy");
  try {
    const surfcap::core::NpyArray array = surfcap::core::read_npy(path);
    if (array.bytes.size() != array.size() * surfcap::core::dtype_size(array.dtype)) __builtin_trap();
    surfcap::core::read_npy_as_double(path, std::vector<long>(array.shape.size(), -1));
  } catch (const surfcap::core::Error&) {
  }
  return 0;
}
