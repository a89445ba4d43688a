#include "linalg/petsc_environment.hpp"

#include <petsc.h>

#include <cctype>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"

namespace biota::linalg {
namespace {
bool we_initialized = false;

void check(PetscErrorCode ierr, const char* what) {
  if (ierr) throw std::runtime_error(std::string("PETSc error in ") + what);
}

std::string last_message;

/// Records the first message of an error (where it was raised) and returns its code, printing
/// nothing: the caller turns the code into an exception (BIOTA_PETSC), and the job's error path
/// prints one line.
PetscErrorCode record_error(MPI_Comm, int, const char*, const char*, PetscErrorCode code,
                            PetscErrorType type, const char* message, void*) {
  if (type == PETSC_ERROR_INITIAL) {
    // On one line: its lines joined by "; ", runs of blanks by one space.
    last_message.clear();
    std::string gap;
    for (const char* c = message ? message : ""; *c; ++c) {
      if (*c == '\n')
        gap = "; ";
      else if (std::isspace(static_cast<unsigned char>(*c)))
        gap = gap.empty() ? " " : gap;
      else {
        if (!last_message.empty()) last_message += gap;
        gap.clear();
        last_message += *c;
      }
    }
  }
  return code;
}

std::vector<std::string> split_words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// PETSc option names start with '-' followed by a letter; "-1e-3" is a value.
bool is_option_name(const std::string& w) {
  return w.size() > 1 && w[0] == '-' && std::isalpha(static_cast<unsigned char>(w[1]));
}
}  // namespace

bool initialized() {
  PetscBool init = PETSC_FALSE;
  PetscInitialized(&init);
  return init == PETSC_TRUE;
}

std::string version() {
  return std::to_string(PETSC_VERSION_MAJOR) + "." + std::to_string(PETSC_VERSION_MINOR) + "." +
         std::to_string(PETSC_VERSION_SUBMINOR);
}

void initialize(const std::vector<std::string>& petsc_args) {
  std::vector<std::string> args{"biota"};
  args.insert(args.end(), petsc_args.begin(), petsc_args.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  initialize(static_cast<int>(args.size()), argv.data());
}

void initialize(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    std::string w = argv[i];
    if (i == 1 && !is_option_name(w))
      throw core::InputError("PETSc options after '--' must start with '-<name>', got '" + w + "'");
  }
  if (!initialized()) {
    int mpi_init = 0;
    MPI_Initialized(&mpi_init);
    if (!mpi_init) throw std::logic_error("linalg::initialize: MPI_Init must come first");
    check(PetscInitialize(&argc, &argv, nullptr, nullptr), "PetscInitialize");
    check(PetscPushErrorHandler(record_error, nullptr), "PetscPushErrorHandler");
    we_initialized = true;
  } else {
    std::string joined;
    for (int i = 1; i < argc; ++i) joined += std::string(argv[i]) + " ";
    check(PetscOptionsInsertString(nullptr, joined.c_str()), "PetscOptionsInsertString");
  }
}

void ensure_initialized() {
  if (!initialized()) initialize(std::vector<std::string>{});
}

void finalize() {
  if (we_initialized && initialized()) {
    PetscFinalize();
    we_initialized = false;
  }
}

void insert_prefixed_options(const std::string& options, const std::string& prefix,
                             const std::string& key) {
  ensure_initialized();
  const auto words = split_words(options);
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& name = words[i];
    if (!is_option_name(name))
      throw core::InputError(key + " = \"" + options + "\": '" + name +
                             "' is not a PETSc option name (expected -" + prefix + "...)");
    if (name.rfind("-" + prefix, 0) != 0)
      throw core::InputError(key + " = \"" + options + "\": option " + name +
                             " does not start with -" + prefix);
    std::string value;
    if (i + 1 < words.size() && !is_option_name(words[i + 1])) value = words[++i];
    PetscBool set = PETSC_FALSE;
    check(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set), "PetscOptionsHasName");
    if (set) continue;  // the command line wins
    check(PetscOptionsSetValue(nullptr, name.c_str(), value.empty() ? nullptr : value.c_str()),
          "PetscOptionsSetValue");
  }
}

void clear_options(const std::string& options) {
  for (const auto& w : split_words(options))
    if (is_option_name(w))
      check(PetscOptionsClearValue(nullptr, w.c_str()), "PetscOptionsClearValue");
}

void check_unused_options(const std::string& prefix, const std::string& source) {
  PetscInt n = 0;
  char** names = nullptr;
  char** values = nullptr;
  check(PetscOptionsLeftGet(nullptr, &n, &names, &values), "PetscOptionsLeftGet");
  std::string bad;
  std::vector<std::string> bad_names;
  for (PetscInt i = 0; i < n; ++i) {
    std::string name = names[i];  // stored without the leading '-'
    if (name.rfind(prefix, 0) == 0) {
      bad += (bad.empty() ? "-" : ", -") + name;
      bad_names.push_back("-" + name);
    }
  }
  PetscOptionsLeftRestore(nullptr, &n, &names, &values);
  // Remove them so a caller that recovers (tests, tools) is not hit by them again.
  for (const auto& name : bad_names) PetscOptionsClearValue(nullptr, name.c_str());
  if (!bad.empty())
    throw core::InputError("unknown or unused PETSc option(s): " + bad + " (from " + source +
                           " or the command line after '--'; run with -help for the options "
                           "of the chosen solver)");
}

std::string last_error_message() {
  return last_message;
}

}  // namespace biota::linalg
