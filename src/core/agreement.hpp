#pragma once
/// \file agreement.hpp
/// \brief One error path for all ranks: an agreement point where every rank learns whether any
/// rank failed, and the test-only fault injection hook.
///
/// `ErrorAgreement::run(fn)` runs `fn` on every rank and then meets the other ranks: if any rank
/// threw, every rank throws the same `AgreedError` (message and exit code of the lowest failing
/// rank). A failing rank waits at most `grace` seconds for the others: if they are stuck in a
/// collective the failing rank never joined, it prints its one-line message and aborts the job
/// (MPI_Abort with the error's exit code). Destructors must not enter collectives while
/// unwinding (see `UnwindGuard`), or the failing rank would never reach the agreement point.
#include <mpi.h>

#include <exception>
#include <stdexcept>
#include <string>
#include <string_view>

namespace biota::core {

/// \brief An error every rank of the communicator knows about (thrown on all of them).
class AgreedError : public std::runtime_error {
 public:
  AgreedError(int exit_code, const std::string& message)
      : std::runtime_error(message), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

/// \brief Exit code for an exception: InputError 2, UnstableError 3, AgreedError its own, else 1.
int exit_code_of(const std::exception& e);

/// \brief Records how many exceptions were in flight at construction; `unwinding()` is true in a
/// destructor that runs because of a newer exception (then: no collective calls, leak instead).
class UnwindGuard {
 public:
  UnwindGuard() : count_(std::uncaught_exceptions()) {}
  bool unwinding() const { return std::uncaught_exceptions() > count_; }

 private:
  int count_;
};

/// \brief The agreement point of a communicator (its own duplicate, so it can never match a
/// collective of the code it guards).
class ErrorAgreement {
 public:
  /// \brief Collective. `grace_seconds` < 0: from BIOTA_ERROR_GRACE (s), default 10.
  explicit ErrorAgreement(MPI_Comm comm, double grace_seconds = -1);
  ~ErrorAgreement();
  ErrorAgreement(const ErrorAgreement&) = delete;
  ErrorAgreement& operator=(const ErrorAgreement&) = delete;

  /// \brief How a rank that did not fail waits for the others: in MPI_Wait (which may spin a
  /// core), or polling with short sleeps, when the others run work that should have the cores
  /// to itself (a benchmark case on one rank).
  enum class Wait { kBlock, kSleep };
  /// \brief Run `fn` on this rank, then agree. Returns the maximum of `flag` over ranks (e.g. a
  /// signal number) if no rank failed; throws AgreedError on every rank otherwise.
  template <class F>
  int run(F&& fn, int flag = 0, Wait wait = Wait::kBlock) {
    std::exception_ptr failure;
    try {
      fn();
    } catch (...) {
      failure = std::current_exception();
    }
    return agree(failure, flag, wait);
  }
  /// \brief The agreement point itself (collective).
  int agree(std::exception_ptr local_failure, int flag = 0, Wait wait = Wait::kBlock);
  /// \brief Extra line printed with the message if the job has to be aborted (e.g. the last good
  /// checkpoint).
  void set_note(std::string note) { note_ = std::move(note); }
  double grace_seconds() const { return grace_; }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  double grace_;
  std::string note_;
};

/// \brief Test-only fault injection. BIOTA_TEST_FAIL="<point>@<rank>[@<step>]" (several separated
/// by commas) makes `fault_injected(point, rank, step)` true on that rank (at that step, or at
/// every step if none is given). Points used: step, health, output, checkpoint, end,
/// checkpoint_close, output_close, late_signal, sigterm, disk_full. Never set it outside tests.
bool fault_injected(std::string_view point, int rank, long long step = -1);

}  // namespace biota::core
