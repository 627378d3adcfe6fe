#include "solver/parallel/mpi_communicator.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

namespace talus {

namespace {

void check(int code, const char* call) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw std::runtime_error(std::string(call) + " failed: " + std::string(text, length));
}

// Byte counts as MPI's int, refused beyond 2 GiB a message (a halo or migration that large is a
// bug; the gathers and broadcasts of whole states go in rounds).
int count_of(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(2147483647))
    throw std::runtime_error("an MPI message of " + std::to_string(bytes) + " bytes (over 2 GiB)");
  return static_cast<int>(bytes);
}

// The most bytes one collective moves (its counts and displacements are MPI's ints): a larger
// payload (a gathered step state for a checkpoint: some 125 bytes a particle, 2.5 GB at 2e7
// particles) travels in rounds of at most this many. 1 GiB, or TALUS_MPI_MESSAGE_BYTES (the
// tests make it a few kilobytes, so that their small states take several rounds).
std::size_t message_limit() {
  static const std::size_t limit = [] {
    const char* v = std::getenv("TALUS_MPI_MESSAGE_BYTES");
    const long long n = v && *v ? std::atoll(v) : 0;
    return n > 0 && n <= (1LL << 30) ? static_cast<std::size_t>(n) : std::size_t(1) << 30;
  }();
  return limit;
}

// How long a wait tests its collective in a loop before it sleeps between tests (MpiCommunicator
// sets it: see there).
std::chrono::microseconds spin_budget(20);

// Waits until `done()` (a test of nonblocking requests) says so: tests in a loop for
// spin_budget, then sleeps between tests, 10 to 200 microseconds, so that a rank waiting for a
// slower one gives its core away. Open MPI's blocking collectives spin instead: with more ranks
// than cores (CI's two cores running three ranks, or a busy machine) a spinning rank takes the
// core the others need, and a step of milliseconds took seconds. A sleep overshoots by tens of
// microseconds, and a GPU's step has some eight collectives: where every rank has a core of its
// own, the loop tests longer.
template <class Test>
void wait_until(Test&& done) {
  const auto start = std::chrono::steady_clock::now();
  auto pause = std::chrono::microseconds(10);
  while (!done()) {
    if (std::chrono::steady_clock::now() - start < spin_budget) continue;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(200));
  }
}

// A nonblocking collective's request, waited for.
void wait(MPI_Request& request, const char* call) {
  wait_until([&] {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), call);
    return done != 0;
  });
}

// Several requests (point-to-point messages) waited for at once; their statuses into `statuses`.
void wait_all(std::vector<MPI_Request>& requests, std::vector<MPI_Status>& statuses,
              const char* call) {
  statuses.resize(requests.size());
  if (requests.empty()) return;
  wait_until([&] {
    int done = 0;
    check(MPI_Testall(static_cast<int>(requests.size()), requests.data(), &done, statuses.data()),
          call);
    return done != 0;
  });
}

// The tag of exchange_sized's messages (no other point-to-point messages are sent).
constexpr int kSizedTag = 7;

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
    // The ranks on this node (a collective): where each has a core of its own, a wait tests for
    // up to 2 ms before it sleeps (the other ranks' answers come within a step's stage); with
    // more ranks than cores, 20 microseconds. TALUS_MPI_SPIN_US sets it.
    MPI_Comm node;
    check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node),
          "MPI_Comm_split_type");
    check(MPI_Comm_size(node, &node_size_), "MPI_Comm_size");
    MPI_Comm_free(&node);
    const unsigned cores = std::thread::hardware_concurrency();
    spin_budget = std::chrono::microseconds(
        cores > 0 && static_cast<unsigned>(node_size_) <= cores ? 2000 : 20);
    if (const char* v = std::getenv("TALUS_MPI_SPIN_US"); v && *v) {
      const long long us = std::atoll(v);
      if (us >= 0) spin_budget = std::chrono::microseconds(us);
    }
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int node_size() const override { return node_size_; }
  double sum(double local) const override { return reduce(local, MPI_DOUBLE, MPI_SUM); }
  double max(double local) const override { return reduce(local, MPI_DOUBLE, MPI_MAX); }
  long long sum(long long local) const override { return reduce(local, MPI_LONG_LONG, MPI_SUM); }
  std::vector<Bytes> exchange(const std::vector<Bytes>& to) const override {
    std::vector<int> send_counts(size_), recv_counts(size_), send_at(size_), recv_at(size_);
    for (int r = 0; r < size_; ++r) send_counts[r] = count_of(to.at(r).size());
    MPI_Request request;
    check(MPI_Ialltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT,
                        MPI_COMM_WORLD, &request),
          "MPI_Ialltoall");
    wait(request, "MPI_Ialltoall");
    std::size_t send_total = 0, recv_total = 0;
    for (int r = 0; r < size_; ++r) {
      send_at[r] = count_of(send_total);
      recv_at[r] = count_of(recv_total);
      send_total += send_counts[r];
      recv_total += recv_counts[r];
    }
    Bytes send(send_total + 1), recv(recv_total + 1);  // + 1: never a null buffer
    for (int r = 0; r < size_; ++r)
      std::copy(to[r].begin(), to[r].end(), send.begin() + send_at[r]);
    check(MPI_Ialltoallv(send.data(), send_counts.data(), send_at.data(), MPI_BYTE, recv.data(),
                         recv_counts.data(), recv_at.data(), MPI_BYTE, MPI_COMM_WORLD, &request),
          "MPI_Ialltoallv");
    wait(request, "MPI_Ialltoallv");
    std::vector<Bytes> from(size_);
    for (int r = 0; r < size_; ++r)
      from[r].assign(recv.begin() + recv_at[r], recv.begin() + recv_at[r] + recv_counts[r]);
    return from;
  }
  void exchange_sized(const char* out, const std::vector<std::size_t>& out_sizes, char* in,
                      const std::vector<std::size_t>& in_sizes) const override {
    if (static_cast<int>(out_sizes.size()) != size_ || static_cast<int>(in_sizes.size()) != size_)
      throw std::runtime_error("exchange_sized: sizes for " + std::to_string(out_sizes.size()) +
                               " and " + std::to_string(in_sizes.size()) + " ranks, not " +
                               std::to_string(size_));
    std::vector<MPI_Request> requests;
    std::vector<int> from;  // the receives' ranks, in the order of their requests
    requests.reserve(2 * static_cast<std::size_t>(size_));
    std::size_t send_at = 0, recv_at = 0, own_send = 0, own_recv = 0;
    // The receives first, so that the sends find them posted.
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) {
        own_recv = recv_at;
      } else if (in_sizes[r] > 0) {
        requests.emplace_back();
        from.push_back(r);
        check(MPI_Irecv(in + recv_at, count_of(in_sizes[r]), MPI_BYTE, r, kSizedTag, MPI_COMM_WORLD,
                        &requests.back()),
              "MPI_Irecv");
      }
      recv_at += in_sizes[r];
    }
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) {
        own_send = send_at;
      } else if (out_sizes[r] > 0) {
        requests.emplace_back();
        check(MPI_Isend(out + send_at, count_of(out_sizes[r]), MPI_BYTE, r, kSizedTag,
                        MPI_COMM_WORLD, &requests.back()),
              "MPI_Isend");
      }
      send_at += out_sizes[r];
    }
    if (out_sizes[rank_] != in_sizes[rank_])
      throw std::runtime_error("exchange_sized: this rank's own block disagrees");
    if (out_sizes[rank_] > 0)
      std::copy(out + own_send, out + own_send + out_sizes[rank_], in + own_recv);
    std::vector<MPI_Status> statuses;
    wait_all(requests, statuses, "MPI_Isend/MPI_Irecv");
    // A longer message fails its receive (MPI_ERR_TRUNCATE, thrown above); a shorter one here.
    for (std::size_t k = 0; k < from.size(); ++k) {
      int got = 0;
      check(MPI_Get_count(&statuses[k], MPI_BYTE, &got), "MPI_Get_count");
      if (static_cast<std::size_t>(got) != in_sizes[from[k]])
        throw std::runtime_error("exchange_sized: rank " + std::to_string(from[k]) + " sent " +
                                 std::to_string(got) + " bytes, not " +
                                 std::to_string(in_sizes[from[k]]));
    }
  }
  // Every rank's bytes to every rank: the sizes first (64-bit), then rounds in which each rank
  // sends its next piece of at most message_limit() / size bytes, until the largest is through.
  std::vector<Bytes> all_gather(const Bytes& mine) const override {
    const long long size = static_cast<long long>(mine.size());
    std::vector<long long> sizes(size_);
    MPI_Request request;
    check(MPI_Iallgather(&size, 1, MPI_LONG_LONG, sizes.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD,
                         &request),
          "MPI_Iallgather");
    wait(request, "MPI_Iallgather");
    const long long piece = std::max<long long>(1, message_limit() / size_);
    const long long largest = *std::max_element(sizes.begin(), sizes.end());
    std::vector<Bytes> out(size_);
    for (int r = 0; r < size_; ++r) out[r].resize(static_cast<std::size_t>(sizes[r]));
    std::vector<int> counts(size_), at(size_);
    Bytes round;
    const char none = 0;  // never a null buffer
    for (long long offset = 0; offset < largest; offset += piece) {
      int total = 0;
      for (int r = 0; r < size_; ++r) {
        counts[r] = static_cast<int>(std::clamp<long long>(sizes[r] - offset, 0, piece));
        at[r] = total, total += counts[r];
      }
      round.resize(static_cast<std::size_t>(total) + 1);
      const char* send = counts[rank_] > 0 ? mine.data() + offset : &none;
      check(MPI_Iallgatherv(send, counts[rank_], MPI_BYTE, round.data(), counts.data(), at.data(),
                            MPI_BYTE, MPI_COMM_WORLD, &request),
            "MPI_Iallgatherv");
      wait(request, "MPI_Iallgatherv");
      for (int r = 0; r < size_; ++r)
        std::copy(round.begin() + at[r], round.begin() + at[r] + counts[r],
                  out[r].begin() + offset);
    }
    return out;
  }
  void broadcast(Bytes& bytes, int root) const override {
    long long n = static_cast<long long>(bytes.size());
    MPI_Request request;
    check(MPI_Ibcast(&n, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD, &request), "MPI_Ibcast");
    wait(request, "MPI_Ibcast");
    bytes.resize(static_cast<std::size_t>(n) + 1);
    broadcast(bytes.data(), static_cast<std::size_t>(n), root);
    bytes.resize(static_cast<std::size_t>(n));
  }
  // In rounds of at most message_limit() bytes (a checkpoint's state for a resume).
  void broadcast(char* data, std::size_t size, int root) const override {
    for (std::size_t offset = 0; offset < size; offset += message_limit()) {
      const std::size_t part = std::min(size - offset, message_limit());
      MPI_Request request;
      check(MPI_Ibcast(data + offset, count_of(part), MPI_BYTE, root, MPI_COMM_WORLD, &request),
            "MPI_Ibcast");
      wait(request, "MPI_Ibcast");
    }
  }
  int broadcast(int value, int root) const override {
    MPI_Request request;
    check(MPI_Ibcast(&value, 1, MPI_INT, root, MPI_COMM_WORLD, &request), "MPI_Ibcast");
    wait(request, "MPI_Ibcast");
    return value;
  }

 private:
  template <class T>
  static T reduce(T local, MPI_Datatype type, MPI_Op op) {
    T out{};
    MPI_Request request;
    check(MPI_Iallreduce(&local, &out, 1, type, op, MPI_COMM_WORLD, &request), "MPI_Iallreduce");
    wait(request, "MPI_Iallreduce");
    return out;
  }

  int rank_ = 0, size_ = 1, node_size_ = 1;  // node_size_: ranks on this node
};

}  // namespace

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

MpiSession::MpiSession() {
  if (!launched_by_mpi()) {
    world_ = std::make_shared<SerialCommunicator>();
    return;
  }
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  initialized_ = true;
  world_ = std::make_shared<MpiCommunicator>();
}

MpiSession::~MpiSession() {
  if (initialized_) MPI_Finalize();
}

int MpiSession::rank() const {
  return world_->rank();
}
int MpiSession::size() const {
  return world_->size();
}

void MpiSession::abort(int code) const {
  if (initialized_) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

}  // namespace talus
