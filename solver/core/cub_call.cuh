// CUB's two-call pattern in one place: the first call asks how much temporary storage the
// algorithm needs, the second runs it. Included only from .cu files.
#pragma once

#include <cstddef>

#include "solver/core/cuda_check.hpp"
#include "solver/core/device_buffer.hpp"

namespace talus {

// `call(void* storage, std::size_t& bytes)` is the CUB algorithm with its arguments bound; `temp`
// grows (with slack, DeviceBuffer::grow_to) to what it asks for and is kept for the next call.
// (While a stream is captured into a graph, the storage must already be large enough: a graph
// step follows a step launched stage by stage with the same sizes, which grew it.)
template <class Call>
void cub_call(DeviceBuffer<unsigned char>& temp, Call&& call) {
  std::size_t bytes = 0;
  TALUS_CUDA_CHECK(call(nullptr, bytes));
  temp.grow_to(bytes);
  bytes = temp.size();
  TALUS_CUDA_CHECK(call(temp.data(), bytes));
}

}  // namespace talus
