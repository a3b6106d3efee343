// Runs a third-party parser in a forked child: see isolate.hpp for why. The child writes its
// answer (a status byte, then the encoded result or an error message) to an anonymous memory file
// it shares with the parent, and leaves with _exit so that nothing of the parent's state (atexit
// handlers, stdio buffers, thread pools) runs twice.
#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <sstream>
#include <thread>

#include "laserfit/core/error.hpp"
#include "laserfit/core/isolate.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define LASERFIT_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LASERFIT_ASAN 1
#endif
#endif
#ifdef LASERFIT_ASAN
#include <sanitizer/common_interface_defs.h>
// The AddressSanitizer runtime of clang 14 (Debian 12) does not lock its allocator, thread
// registry and stack depot across fork(): a child forked while another thread held one of them
// (a worker refilling its allocation cache, a thread starting or ending) deadlocks at its first
// allocation. LLVM 18 installs a pthread_atfork handler that takes exactly these locks
// (llvm-project pull request 75290); until then laserfit takes them around its own fork.
namespace __lsan {
void LockThreadRegistry();
void UnlockThreadRegistry();
void LockAllocator();
void UnlockAllocator();
}  // namespace __lsan
namespace __sanitizer {
void StackDepotLockAll();
void StackDepotUnlockAll();
}  // namespace __sanitizer
#endif

namespace laserfit {
namespace {

enum class Reply : char { Result = 'R', Error = 'E' };

bool write_all(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

std::string read_all(int fd, const std::string& path) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw Error(path, "cannot read the reader process's answer");
  std::string bytes(static_cast<size_t>(st.st_size), '\0');
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n =
        ::pread(fd, bytes.data() + done, bytes.size() - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(path, "cannot read the reader process's answer");
    done += static_cast<size_t>(n);
  }
  return bytes;
}

// Mapped and resident memory of a process (MiB), 0 when unknown (/proc/<pid>/statm).
double statm_mib(pid_t pid, int field) {
  std::ifstream statm("/proc/" + std::to_string(pid) + "/statm");
  double pages[2] = {0, 0};
  if (!(statm >> pages[0] >> pages[1])) return 0.0;
  return pages[field] * static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}
[[maybe_unused]] double mapped_mib(pid_t pid) { return statm_mib(pid, 0); }
double resident_mib(pid_t pid) { return statm_mib(pid, 1); }

std::string seconds(double s) {
  std::ostringstream o;
  o << s;
  return o.str();
}

// The child: limits, silence, read, answer, _exit. Never returns.
[[noreturn]] void child(int fd, const std::string& path, const std::string& reader,
                        const IsolationLimits& limits, const std::function<std::string()>& read) {
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  // A crash is the parent's to report: no sanitizer or debugger handler of the parent's runs.
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
#ifdef LASERFIT_ASAN
  // Under ASan the signals stay ASan's, and a parser's crash ends in ASan's death callback: a
  // fuzzer's (libFuzzer's) would file the parent's input as its own finding, from the child.
  __sanitizer_set_death_callback(nullptr);
#endif
#ifndef LASERFIT_ASAN  // AddressSanitizer reserves terabytes of address space for its shadow
  // The limit is on what the reader adds: the forked process already maps what the parent
  // mapped (libraries, thread stacks, a benchmark's data), which can be gigabytes.
  if (limits.memory_mib > 0) {
    const double inherited_mib = mapped_mib(::getpid());
    const auto bytes = static_cast<rlim_t>((inherited_mib + limits.memory_mib) * 1024.0 * 1024.0);
    const rlimit as{bytes, bytes};
    ::setrlimit(RLIMIT_AS, &as);
  }
#endif
  const int null = ::open("/dev/null", O_WRONLY);  // the parsers' chatter is not our output
  if (null >= 0) ::dup2(null, STDOUT_FILENO), ::dup2(null, STDERR_FILENO);
  std::string answer;
  try {
    answer = static_cast<char>(Reply::Result) + read();
  } catch (const std::bad_alloc&) {
    answer = static_cast<char>(Reply::Error) + path + ": " + reader +
             " could not allocate memory (a corrupt size in the file, or more than its limit of " +
             seconds(limits.memory_mib) + " MiB)";
  } catch (const std::exception& e) {
    // Parsers catch a failed allocation themselves and report it as their own error.
    const std::string what = e.what();
    std::string hint;
    if (what.find("bad_alloc") != std::string::npos ||
        what.find("OutOfMemory") != std::string::npos)
      hint = " (" + reader + " could not allocate memory: a corrupt size in the file, or more " +
             "than its limit of " + seconds(limits.memory_mib) + " MiB)";
    answer = static_cast<char>(Reply::Error) + what + hint;
  } catch (...) {
    answer = static_cast<char>(Reply::Error) + path + ": " + reader + " threw an unknown exception";
  }
  ::_exit(write_all(fd, answer) ? 0 : 3);
}

#ifdef LASERFIT_ASAN
// The number of threads of this process (/proc/self/stat, field 20), 0 when unknown.
int thread_count() {
  std::ifstream stat("/proc/self/stat");
  std::string line;
  std::getline(stat, line);
  const size_t comm_end = line.rfind(')');  // the command name may hold spaces
  if (comm_end == std::string::npos) return 0;
  std::istringstream fields(line.substr(comm_end + 2));
  std::string field;
  for (int i = 3; i <= 20 && fields >> field; ++i)
    if (i == 20) return std::atoi(field.c_str());
  return 0;
}
#endif

// fork() with the sanitizer's locks held (see the includes); a plain fork() otherwise. Nothing
// between the locking and the fork allocates. A process with one thread forks without them: no
// other thread can hold them, and unlocking the stack depot writes every page of its table, which
// the fork has just shared, so both processes copy them all (half a fuzzer's time, `perf`).
pid_t fork_safely() {
#ifdef LASERFIT_ASAN
  if (thread_count() == 1) return ::fork();
  __lsan::LockThreadRegistry();
  __lsan::LockAllocator();
  __sanitizer::StackDepotLockAll();
  const pid_t pid = ::fork();
  const int fork_errno = errno;
  __sanitizer::StackDepotUnlockAll();
  __lsan::UnlockAllocator();
  __lsan::UnlockThreadRegistry();
  errno = fork_errno;
  return pid;
#else
  return ::fork();
#endif
}

constexpr int kTimedOut = -1, kOutOfMemory = -2, kLost = -3;

// Sleeps for `nap`, or less when the child exits first: a pidfd turns readable at its exit, so a
// short read is answered at once rather than at the next poll (a fuzzer reads thousands).
void nap_until_exit(int pidfd, std::chrono::microseconds nap) {
  if (pidfd < 0) return std::this_thread::sleep_for(nap);  // a kernel before 5.3
  pollfd p{pidfd, POLLIN, 0};
  const timespec t{0, static_cast<long>(nap.count()) * 1000};
  ::ppoll(&p, 1, &t, nullptr);
}

// Waits for the child; kills it at the deadline or when it holds more than the memory limit on
// top of what it inherited. Returns its wait status, kTimedOut or kOutOfMemory.
int wait_child(pid_t pid, const IsolationLimits& limits, double parent_resident_mib) {
  const auto t0 = std::chrono::steady_clock::now();
  const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  struct Closer {
    int fd;
    ~Closer() {
      if (fd >= 0) ::close(fd);
    }
  } closer{pidfd};
  auto nap = std::chrono::microseconds(200);
  for (;;) {
    int status = 0;
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) return status;
    if (r < 0 && errno != EINTR) return kLost;  // reaped elsewhere (SIGCHLD ignored)
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bool late = limits.timeout_s > 0 && waited > limits.timeout_s;
    const bool huge =
        limits.memory_mib > 0 && resident_mib(pid) > parent_resident_mib + limits.memory_mib;
    if (late || huge) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      return late ? kTimedOut : kOutOfMemory;
    }
    nap_until_exit(pidfd, nap);
    nap = std::min(nap * 2, std::chrono::microseconds(20000));
  }
}

std::string answer_of(int fd, int status, const std::string& path, const std::string& reader,
                      const IsolationLimits& limits) {
  if (status == kTimedOut)
    throw Error(path, reader + " took longer than " + seconds(limits.timeout_s) +
                          " s (raise --timeout if the file is just large)");
  if (status == kOutOfMemory)
    throw Error(path, reader + " used more than " + seconds(limits.memory_mib) + " MiB of memory");
  if (status == kLost) throw Error(path, reader + ": lost track of the reader process");
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    throw Error(path,
                reader + " crashed (signal " + std::to_string(sig) + ", " + ::strsignal(sig) + ")");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Error(path,
                reader + " exited abnormally (status " + std::to_string(WEXITSTATUS(status)) + ")");
  const std::string bytes = read_all(fd, path);
  if (bytes.empty()) throw Error(path, reader + " gave no answer");
  if (bytes[0] == static_cast<char>(Reply::Error)) throw Error(bytes.substr(1));
  if (bytes[0] != static_cast<char>(Reply::Result))
    throw Error(path, "the reader process answered garbage (status)");
  return bytes.substr(1);
}

}  // namespace

std::string run_isolated(const std::string& path, const std::string& reader,
                         const IsolationLimits& limits, const std::function<std::string()>& read) {
  if (!limits.isolate) return read();
  if (!(limits.timeout_s >= 0) || !(limits.memory_mib >= 0))
    throw Error(path, "the reader's time and memory limits must be >= 0");
  const int fd = ::memfd_create("laserfit-reader", MFD_CLOEXEC);
  if (fd < 0) throw Error(path, std::string("cannot isolate the reader: ") + std::strerror(errno));
  const double resident = resident_mib(::getpid());  // the child starts with these pages
  const pid_t pid = fork_safely();
  if (pid < 0) {
    ::close(fd);
    throw Error(path, std::string("cannot start the reader process: ") + std::strerror(errno));
  }
  if (pid == 0) child(fd, path, reader, limits, read);
  try {
    std::string answer = answer_of(fd, wait_child(pid, limits, resident), path, reader, limits);
    ::close(fd);
    return answer;
  } catch (...) {
    ::close(fd);
    throw;
  }
}

}  // namespace laserfit
