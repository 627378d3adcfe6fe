#include "solver/parallel/mpi_communicator.hpp"

#include <mpi.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace talus {

namespace {

void check(int code, const char* call) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw std::runtime_error(std::string(call) + " failed: " + std::string(text, length));
}

// Byte counts as MPI's int, refused beyond 2 GiB a message (a halo that large is a bug).
int count_of(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(2147483647))
    throw std::runtime_error("an MPI message of " + std::to_string(bytes) + " bytes (over 2 GiB)");
  return static_cast<int>(bytes);
}

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  double sum(double local) const override {
    double out = 0;
    check(MPI_Allreduce(&local, &out, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  double max(double local) const override {
    double out = 0;
    check(MPI_Allreduce(&local, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  long long sum(long long local) const override {
    long long out = 0;
    check(MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  std::vector<Bytes> exchange(const std::vector<Bytes>& to) const override {
    std::vector<int> send_counts(size_), recv_counts(size_), send_at(size_), recv_at(size_);
    for (int r = 0; r < size_; ++r) send_counts[r] = count_of(to.at(r).size());
    check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT,
                       MPI_COMM_WORLD),
          "MPI_Alltoall");
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
    check(MPI_Alltoallv(send.data(), send_counts.data(), send_at.data(), MPI_BYTE, recv.data(),
                        recv_counts.data(), recv_at.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Alltoallv");
    std::vector<Bytes> from(size_);
    for (int r = 0; r < size_; ++r)
      from[r].assign(recv.begin() + recv_at[r], recv.begin() + recv_at[r] + recv_counts[r]);
    return from;
  }
  std::vector<Bytes> all_gather(const Bytes& mine) const override {
    const int count = count_of(mine.size());
    std::vector<int> counts(size_), at(size_);
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD),
          "MPI_Allgather");
    std::size_t total = 0;
    for (int r = 0; r < size_; ++r) at[r] = count_of(total), total += counts[r];
    Bytes all(total + 1);
    Bytes send(mine);
    send.push_back(0);
    check(MPI_Allgatherv(send.data(), count, MPI_BYTE, all.data(), counts.data(), at.data(),
                         MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    std::vector<Bytes> out(size_);
    for (int r = 0; r < size_; ++r)
      out[r].assign(all.begin() + at[r], all.begin() + at[r] + counts[r]);
    return out;
  }
  void broadcast(Bytes& bytes, int root) const override {
    long long n = static_cast<long long>(bytes.size());
    check(MPI_Bcast(&n, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD), "MPI_Bcast");
    bytes.resize(static_cast<std::size_t>(n) + 1);
    check(MPI_Bcast(bytes.data(), count_of(static_cast<std::size_t>(n)), MPI_BYTE, root,
                    MPI_COMM_WORLD),
          "MPI_Bcast");
    bytes.resize(static_cast<std::size_t>(n));
  }
  int broadcast(int value, int root) const override {
    check(MPI_Bcast(&value, 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Bcast");
    return value;
  }

 private:
  int rank_ = 0, size_ = 1;
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
