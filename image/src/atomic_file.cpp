// Output files (see write.h): what may be replaced, temporaries this process owns, and
// several files replaced all-or-nothing.
//
// A temporary is an unnamed file (O_TMPFILE: nothing is left on disk if the process dies)
// or, where the file system has no O_TMPFILE, a new name created with O_EXCL. Either way
// it is written completely and synced before any output is replaced; at commit an
// unnamed file is linked straight to a destination that does not exist (linkat), or to a
// temporary name that rename() then moves over the existing destination in one step
// (POSIX). Only names this object created are ever removed.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

#include "softpbr/image/write.h"

namespace softpbr::image {

namespace fs = std::filesystem;

namespace {

std::string errno_text(int e) { return std::generic_category().message(e); }

fs::path folder_of(const fs::path& path) { return path.parent_path().empty() ? fs::path(".") : path.parent_path(); }

// The longest file name the folder allows (255 on Linux file systems).
std::size_t name_max(const fs::path& folder) {
  const long n = ::pathconf(folder.c_str(), _PC_NAME_MAX);
  return n > 0 ? static_cast<std::size_t>(n) : 255;
}

const char* kind(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a named pipe";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// "" when the existing entry at `path` may be replaced (it is a regular file) or there is none.
std::string entry_problem(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return {};
    return "cannot write: " + errno_text(errno);
  }
  if (S_ISREG(st.st_mode)) return {};
  if (S_ISDIR(st.st_mode)) return "cannot write: it is a folder";
  return std::string("cannot write: it is ") + kind(st.st_mode) + ", not a regular file (an output is a regular file or a new name)";
}

[[noreturn]] void fail(const fs::path& path, const std::string& what) { throw std::runtime_error(path.string() + ": " + what); }

// A temporary name for `path` in its folder, within the folder's NAME_MAX:
// ".NAME.tmp-XXXXXXXXXX" with NAME cut short when needed.
fs::path temporary_name(const fs::path& path, std::mt19937_64& random) {
  static constexpr char kDigits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
  std::string suffix = ".tmp-";
  for (int i = 0; i < 10; ++i) suffix += kDigits[random() % 36];
  const std::string name = path.filename().string();
  const std::size_t room = name_max(folder_of(path)) - 1 - suffix.size();
  std::string tmp(1, '.');  // appended piecewise: GCC 12 warns (-Wrestrict) on "." + string
  tmp.append(name, 0, std::min(name.size(), room));
  tmp.append(suffix);
  return path.parent_path() / tmp;
}

bool write_all(int fd, std::span<const std::uint8_t> bytes, int& error) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      error = errno;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    error = errno;
    return false;
  }
  return true;
}

std::mt19937_64 seeded() {
  std::random_device rd;
  return std::mt19937_64((std::uint64_t{rd()} << 32) ^ rd() ^ static_cast<std::uint64_t>(::getpid()));
}

}  // namespace

std::string output_problem(const fs::path& path) {
  const std::string name = path.filename().string();
  if (name.empty() || name == "." || name == "..") return "cannot write: not a file name";
  if (path.string().find('\0') != std::string::npos) return "cannot write: the name holds a NUL byte";
  const fs::path folder = folder_of(path);
  struct stat st {};
  // The true reason: a missing folder, a file where the folder should be ("-o file/x.png"),
  // a link loop, no permission to look.
  if (::stat(folder.c_str(), &st) != 0) {
    if (errno == ENOENT) return "cannot write: the folder " + folder.string() + " does not exist";
    if (errno == ENOTDIR) return "cannot write: a part of " + folder.string() + " is not a folder";
    if (errno == ELOOP) return "cannot write: the folder " + folder.string() + ": too many levels of symbolic links (a link loop)";
    return "cannot write: the folder " + folder.string() + ": " + std::strerror(errno);
  }
  if (!S_ISDIR(st.st_mode)) return "cannot write: " + folder.string() + " is not a folder";
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    return errno == EROFS ? "cannot write: the folder " + folder.string() + " is on a read-only file system"
                          : "cannot write: no permission to create files in " + folder.string();
  if (const std::size_t max = name_max(folder); name.size() > max)
    return "cannot write: the file name is " + std::to_string(name.size()) + " bytes, over the limit of " +
           std::to_string(max) + " of its folder";
  if (path.string().size() >= PATH_MAX)
    return "cannot write: the path is " + std::to_string(path.string().size()) + " bytes, over the limit of " +
           std::to_string(PATH_MAX - 1);
  return entry_problem(path);
}

OutputFiles::~OutputFiles() { discard(); }

void OutputFiles::discard() noexcept {
  for (Pending& p : pending_) {
    if (!p.temporary.empty()) ::unlink(p.temporary.c_str());  // a name this object created
    if (p.fd >= 0) ::close(p.fd);
  }
  pending_.clear();
}

void OutputFiles::add(const fs::path& path, std::span<const std::uint8_t> bytes) {
  if (const std::string problem = output_problem(path); !problem.empty()) fail(path, problem);
  Pending p;
  p.path = path;
  const fs::path folder = folder_of(path);
  // An unnamed file first; a named one (O_EXCL: never an existing file) where unsupported.
  // (An unnamed file is named through /proc/self/fd: without /proc, a named one.)
  if (::access("/proc/self/fd", X_OK) == 0) p.fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  if (p.fd < 0) {
    std::mt19937_64 random = seeded();
    for (int attempt = 0; attempt < 100 && p.fd < 0; ++attempt) {
      const fs::path tmp = temporary_name(path, random);
      p.fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
      if (p.fd >= 0) p.temporary = tmp;
      else if (errno != EEXIST) fail(path, "cannot create a temporary file in " + folder.string() + ": " + errno_text(errno));
    }
    if (p.fd < 0) fail(path, "cannot create a temporary file in " + folder.string());
  }
  int error = 0;
  const bool ok = write_all(p.fd, bytes, error);
  pending_.push_back(std::move(p));  // discard() removes it from here on
  if (!ok) {
    const Pending failed = pending_.back();
    pending_.pop_back();
    if (!failed.temporary.empty()) ::unlink(failed.temporary.c_str());
    ::close(failed.fd);
    if (error == ENOSPC || error == EDQUOT || error == EFBIG) fail(path, "write failed (disk full?)");
    fail(path, "write failed: " + errno_text(error));
  }
}

namespace {
// Gives the unnamed file `fd` the name `tmp` (a temporary beside `path`), retrying other
// random names while they exist. Throws naming `path`.
fs::path name_temporary(int fd, const fs::path& path, std::mt19937_64& random) {
  const std::string proc = "/proc/self/fd/" + std::to_string(fd);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path tmp = temporary_name(path, random);
    if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) == 0) return tmp;
    if (errno != EEXIST) fail(path, "cannot name the temporary file: " + errno_text(errno));
  }
  fail(path, "cannot name the temporary file");
}
}  // namespace

void OutputFiles::commit() {
  // 1. Every destination is checked again (still a regular file or no file), and an
  //    unnamed file that will replace an existing one gets a temporary name (through
  //    /proc/self/fd). One whose destination does not exist keeps no name at all: it is
  //    linked straight to its destination in step 2, so a kill leaves nothing behind.
  std::mt19937_64 random = seeded();
  std::vector<bool> direct(pending_.size(), false);
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    Pending& p = pending_[i];
    if (const std::string problem = entry_problem(p.path); !problem.empty()) fail(p.path, problem);
    if (!p.temporary.empty()) continue;
    struct stat st {};
    if (::lstat(p.path.c_str(), &st) != 0 && errno == ENOENT) direct[i] = true;
    else p.temporary = name_temporary(p.fd, p.path, random);
  }
  // 2. Only now is any output replaced or created: renames, and links of new names (one
  //    that appeared meanwhile, another writer's, is replaced through a temporary instead).
  std::string replaced;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    Pending& p = pending_[i];
    int e = 0;
    if (direct[i]) {
      const std::string proc = "/proc/self/fd/" + std::to_string(p.fd);
      if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, p.path.c_str(), AT_SYMLINK_FOLLOW) != 0) {
        if (errno != EEXIST) e = errno;
        else p.temporary = name_temporary(p.fd, p.path, random);
      }
    }
    if (e == 0 && !p.temporary.empty() && ::rename(p.temporary.c_str(), p.path.c_str()) != 0) e = errno;
    if (e != 0)
      fail(p.path, "cannot replace it: " + errno_text(e) +
                       (replaced.empty() ? std::string() : " (already replaced: " + replaced + ")"));
    replaced += (replaced.empty() ? "" : ", ") + p.path.string();
    p.temporary.clear();
    ::close(p.fd);
    p.fd = -1;
  }
  pending_.clear();
}

void write_file_atomic(const fs::path& path, std::span<const std::uint8_t> bytes) {
  OutputFiles files;
  files.add(path, bytes);
  files.commit();
}

}  // namespace softpbr::image
