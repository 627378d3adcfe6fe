// The Communicator (domain/communicator.hpp) over MPI_COMM_WORLD (Open MPI; docs/parallel.md):
// the only file of talus that includes mpi.h. MpiSession initializes MPI when the process was
// started by mpirun (or mpiexec) and finalizes it at exit; a process started alone is one rank
// and never touches MPI, so the same talus runs with and without mpirun.
#pragma once

#include <memory>

#include "solver/domain/communicator.hpp"

namespace talus {

// Whether this process was started by an MPI launcher (the environment says so), without
// initializing anything.
bool launched_by_mpi();

class MpiSession {
 public:
  // Initializes MPI when launched_by_mpi(); otherwise holds one rank.
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const;
  int size() const;
  // The world's communicator (a SerialCommunicator for one process).
  std::shared_ptr<const Communicator> world() const { return world_; }
  // Every rank stops at once with `code` (a rank that fails where the others wait in a
  // collective).
  [[noreturn]] void abort(int code) const;

 private:
  bool initialized_ = false;
  std::shared_ptr<const Communicator> world_;
};

}  // namespace talus
