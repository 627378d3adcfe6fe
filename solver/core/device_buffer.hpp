// One explicit owning device array with explicit copies, no mirrored host copy (docs/design.md,
// "Code conventions").
#pragma once

#include <cstddef>
#include <vector>

#include "solver/core/cuda_check.hpp"

namespace talus {

template <class T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  explicit DeviceBuffer(std::size_t count) { resize(count); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept : data_(o.data_), size_(o.size_) {
    o.data_ = nullptr;
    o.size_ = 0;
  }
  ~DeviceBuffer() {
    if (data_) cudaFree(data_);  // no throw from a destructor
  }

  // Exchanges the two arrays (no copy): a gather into a scratch array, then swapped in.
  void swap(DeviceBuffer& o) noexcept {
    T* data = data_;
    const std::size_t size = size_;
    data_ = o.data_, size_ = o.size_;
    o.data_ = data, o.size_ = size;
  }

  void resize(std::size_t count) {
    if (count == size_) return;
    if (data_) TALUS_CUDA_CHECK(cudaFree(data_));
    data_ = nullptr;
    size_ = 0;
    if (count > 0)
      TALUS_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&data_), count * sizeof(T)));
    size_ = count;
  }
  // At least `count` elements, growing by a quarter more than asked (contents are not kept): for
  // lists whose length changes every step, where a cudaFree per step would synchronise and
  // fragment memory.
  void grow_to(std::size_t count) {
    if (size_ < count) resize(count + count / 4 + 64);
  }
  // Room for `count` elements with the first `keep` (<= size()) kept, copied on the device: for
  // arrays that are appended to (a feed's particles). Reallocates only when `count` exceeds
  // size(); the caller chooses how far ahead to grow.
  void grow_keeping(std::size_t count, std::size_t keep) {
    if (count <= size_) return;
    T* grown = nullptr;
    TALUS_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&grown), count * sizeof(T)));
    if (keep > 0) {
      const cudaError_t copied =
          cudaMemcpy(grown, data_, keep * sizeof(T), cudaMemcpyDeviceToDevice);
      if (copied != cudaSuccess) cudaFree(grown);  // the copy's error is the one reported
      TALUS_CUDA_CHECK(copied);
    }
    if (data_) TALUS_CUDA_CHECK(cudaFree(data_));
    data_ = grown;
    size_ = count;
  }
  void upload(const T* host, std::size_t count) {
    resize(count);
    if (count > 0)
      TALUS_CUDA_CHECK(cudaMemcpy(data_, host, count * sizeof(T), cudaMemcpyHostToDevice));
  }
  void upload(const std::vector<T>& host) { upload(host.data(), host.size()); }
  void download(std::vector<T>& host) const {
    host.resize(size_);
    if (size_ > 0)
      TALUS_CUDA_CHECK(cudaMemcpy(host.data(), data_, size_ * sizeof(T), cudaMemcpyDeviceToHost));
  }

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace talus
