#include "core/agreement.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include "core/error.hpp"

namespace biota::core {

int exit_code_of(const std::exception& e) {
  if (auto* a = dynamic_cast<const AgreedError*>(&e)) return a->exit_code();
  if (dynamic_cast<const InputError*>(&e)) return kExitInput;
  if (dynamic_cast<const UnstableError*>(&e)) return kExitUnstable;
  return kExitRuntime;
}

ErrorAgreement::ErrorAgreement(MPI_Comm comm, double grace_seconds) : grace_(grace_seconds) {
  MPI_Comm_dup(comm, &comm_);
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  if (grace_ < 0) {
    grace_ = 10.0;
    if (const char* g = std::getenv("BIOTA_ERROR_GRACE")) grace_ = std::atof(g);
  }
}

ErrorAgreement::~ErrorAgreement() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized && comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

int ErrorAgreement::agree(std::exception_ptr local_failure, int flag, Wait wait) {
  int code = 0;
  std::string message;
  if (local_failure) {
    try {
      std::rethrow_exception(local_failure);
    } catch (const std::exception& e) {
      code = exit_code_of(e);
      message = e.what();
    } catch (...) {
      code = kExitRuntime;
      message = "unknown exception";
    }
    if (code == 0) code = kExitRuntime;
  }
  // Max of (size - rank) over failing ranks names the lowest failing rank.
  int local[2] = {code ? size_ - rank_ : 0, flag}, global[2] = {0, 0};
  MPI_Request req;
  MPI_Iallreduce(local, global, 2, MPI_INT, MPI_MAX, comm_, &req);
  if (!code && wait == Wait::kBlock) {
    MPI_Wait(&req, MPI_STATUS_IGNORE);
  } else if (!code) {
    for (int done = 0; !done;) {
      MPI_Test(&req, &done, MPI_STATUS_IGNORE);
      if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  } else {
    // The others may be stuck in a collective this rank left: wait `grace_`, then abort.
    const double deadline = MPI_Wtime() + grace_;
    int done = 0;
    while (!done) {
      MPI_Test(&req, &done, MPI_STATUS_IGNORE);
      if (done) break;
      if (MPI_Wtime() > deadline) {
        fmt::print(stderr, "biota: error: {}\n", message);
        if (!note_.empty()) fmt::print(stderr, "biota: {}\n", note_);
        fmt::print(stderr,
                   "biota: rank {} failed alone and the other ranks did not reach the agreement "
                   "point within {:g} s: aborting the job\n",
                   rank_, grace_);
        std::fflush(stderr);
        MPI_Abort(comm_, code);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  if (global[0] == 0) return global[1];
  const int root = size_ - global[0];
  int head[2] = {code, static_cast<int>(message.size())};
  MPI_Bcast(head, 2, MPI_INT, root, comm_);
  message.resize(head[1]);
  MPI_Bcast(message.data(), head[1], MPI_CHAR, root, comm_);
  throw AgreedError(head[0], message);
}

bool fault_injected(std::string_view point, int rank, long long step) {
  const char* env = std::getenv("BIOTA_TEST_FAIL");
  if (!env) return false;
  std::string_view all(env);
  while (!all.empty()) {
    const auto comma = all.find(',');
    std::string_view item = all.substr(0, comma);
    all = comma == std::string_view::npos ? std::string_view{} : all.substr(comma + 1);
    const auto at = item.find('@');
    if (at == std::string_view::npos || item.substr(0, at) != point) continue;
    std::string rest(item.substr(at + 1));
    const auto at2 = rest.find('@');
    if (std::atoi(rest.substr(0, at2).c_str()) != rank) continue;
    if (at2 == std::string::npos || std::atoll(rest.substr(at2 + 1).c_str()) == step) return true;
  }
  return false;
}

}  // namespace biota::core
