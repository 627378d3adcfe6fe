// How the ranks of a decomposed run talk (docs/parallel.md): the few collective operations the
// decomposed step needs, as bytes, so that the step and the domain do not include mpi.h. The MPI
// implementation is solver/parallel/mpi_communicator; SerialCommunicator is one process (rank 0 of
// 1), which every collective returns unchanged. Every rank must make the same calls in the same
// order: these are collectives.
#pragma once

#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace talus {

using Bytes = std::vector<char>;

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // The ranks on this rank's node (sharing its cores and memory): size() for ranks of one
  // process or one machine.
  virtual int node_size() const { return size(); }
  virtual double sum(double local) const = 0;
  virtual double max(double local) const = 0;
  virtual long long sum(long long local) const = 0;
  // to[r]: what this rank sends rank r (to[rank()] is returned as from[rank()]); from[r]: what r
  // sent this rank.
  virtual std::vector<Bytes> exchange(const std::vector<Bytes>& to) const = 0;
  // An exchange whose sizes both sides know already (the ghosts' states each step): out_sizes[r]
  // bytes from `out` (one block per rank, in rank order) to rank r, in_sizes[r] bytes from rank r
  // into `in` (likewise); this rank's own block copied. Point to point, no sizes sent: a rank's
  // out_sizes[r] must be rank r's in_sizes[rank()] (a mismatch is an error). Every rank calls it
  // at the same point of the step, as a collective.
  virtual void exchange_sized(const char* out, const std::vector<std::size_t>& out_sizes, char* in,
                              const std::vector<std::size_t>& in_sizes) const = 0;
  // Every rank's bytes, on every rank, in rank order.
  virtual std::vector<Bytes> all_gather(const Bytes& mine) const = 0;
  // `bytes` of rank `root` on every rank.
  virtual void broadcast(Bytes& bytes, int root) const = 0;
  // Rank `root`'s int, on every rank.
  virtual int broadcast(int value, int root) const = 0;
  // Rank `root`'s `size` bytes at `data` into every rank's `data` (one collective: the size is
  // known to all).
  virtual void broadcast(char* data, std::size_t size, int root) const = 0;
};

class SerialCommunicator final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  double sum(double local) const override { return local; }
  double max(double local) const override { return local; }
  long long sum(long long local) const override { return local; }
  std::vector<Bytes> exchange(const std::vector<Bytes>& to) const override { return to; }
  void exchange_sized(const char* out, const std::vector<std::size_t>& out_sizes, char* in,
                      const std::vector<std::size_t>& in_sizes) const override {
    if (out_sizes.size() != 1 || in_sizes.size() != 1 || out_sizes[0] != in_sizes[0])
      throw std::runtime_error("exchange_sized: one rank's sizes disagree");
    if (out_sizes[0] > 0) std::memcpy(in, out, out_sizes[0]);
  }
  std::vector<Bytes> all_gather(const Bytes& mine) const override { return {mine}; }
  void broadcast(Bytes&, int) const override {}
  int broadcast(int value, int) const override { return value; }
  void broadcast(char*, std::size_t, int) const override {}
};

// Plain values in and out of byte buffers (trivially copyable types only).
class ByteWriter {
 public:
  explicit ByteWriter(Bytes& out) : out_(out) {}
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t at = out_.size();
    out_.resize(at + sizeof(T));
    std::memcpy(out_.data() + at, &value, sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<long long>(values.size()));
    const std::size_t at = out_.size();
    out_.resize(at + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(out_.data() + at, values.data(), values.size() * sizeof(T));
  }
  void put_string(const std::string& s) { put_vector(std::vector<char>(s.begin(), s.end())); }

 private:
  Bytes& out_;
};

class ByteReader {
 public:
  explicit ByteReader(const Bytes& in) : in_(in) {}
  bool done() const { return at_ >= in_.size(); }
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, in_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  template <class T>
  std::vector<T> get_vector() {
    const long long n = get<long long>();
    std::vector<T> values(static_cast<std::size_t>(n));
    if (n > 0) std::memcpy(values.data(), in_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return values;
  }
  std::string get_string() {
    const std::vector<char> c = get_vector<char>();
    return std::string(c.begin(), c.end());
  }

 private:
  const Bytes& in_;
  std::size_t at_ = 0;
};

}  // namespace talus

namespace talus {

// Where every rank has finished a stage that may fail on some ranks only: `failure` is this
// rank's (null when it succeeded). When some rank failed, every rank throws std::runtime_error
// with the message of the lowest rank that failed, so that no rank is left waiting in the next
// collective; otherwise returns. A collective.
inline void agree_on_failure(const Communicator& comm, const std::exception_ptr& failure) {
  std::string message;
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
      message = "an unknown exception";
    }
  }
  if (comm.size() == 1) {
    if (failure) std::rethrow_exception(failure);
    return;
  }
  if (comm.max(failure ? 1.0 : 0.0) == 0) return;
  const std::vector<Bytes> all = comm.all_gather(Bytes(message.begin(), message.end()));
  for (int r = 0; r < comm.size(); ++r) {
    if (!all[r].empty()) {
      throw std::runtime_error(std::string(all[r].begin(), all[r].end()) +
                               (r == comm.rank() ? "" : " (rank " + std::to_string(r) + ")"));
    }
  }
  throw std::runtime_error("a rank failed without a message");
}

}  // namespace talus
