// libFuzzer target: the mesh readers (solver/shape/mesh_io.hpp) and the template built from what
// they read. The first byte picks the reader (even: OBJ, odd: STL, ASCII or binary by size); the
// rest is the file. load_shape_file reads it, builds the hull's template and checks convexity, as
// a scene's mesh template does. The readers' std::runtime_error and the builder's
// std::invalid_argument are answers; crashes, sanitizer reports, other exceptions and hangs are
// bugs.
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <stdexcept>

#include "solver/shape/mesh_io.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Not every input is convex: its one-line warning per input on std::cerr would drown the
  // fuzzer's log (sanitizer reports write to the descriptor directly and still appear).
  std::cerr.setstate(std::ios::badbit);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool stl = data[0] & 1;
  const std::string path = talus_fuzz::write_input(data + 1, size - 1, stl ? "in.stl" : "in.obj");
  try {
    talus::load_shape_file(path);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
