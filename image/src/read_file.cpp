// Reading a whole input file without blocking (see read_file.h).
#include "softpbr/image/read_file.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstring>

namespace softpbr::image {

namespace {

FileProblem system_problem(int error) {
  FileProblem p;
  p.error = error;
  switch (error) {
    case ENOENT: p.reason = "no such file"; break;
    case ELOOP: p.reason = "too many levels of symbolic links (a link loop)"; break;
    case EACCES:
    case EPERM: p.reason = "permission denied"; break;
    case ENOTDIR: p.reason = "no such file (a part of its path is not a folder)"; break;
    case ENAMETOOLONG: p.reason = "the file name is too long"; break;
    case ENXIO: p.reason = "is a socket or a device with nothing behind it, not a regular file"; break;
    case EMFILE:
    case ENFILE: p.reason = "cannot open: too many open files"; break;
    default: p.reason = std::string("cannot open: ") + std::strerror(error); break;
  }
  return p;
}

// The reason for anything but a regular file ("" for a regular file).
FileProblem kind_problem(const struct stat& st) {
  FileProblem p;
  if (S_ISREG(st.st_mode)) return p;
  if (S_ISDIR(st.st_mode)) {
    p.folder = true;
    p.reason = "is a folder";
  } else if (S_ISFIFO(st.st_mode)) {
    p.reason = "is a named pipe (FIFO), not a regular file";
  } else if (S_ISCHR(st.st_mode)) {
    p.reason = "is a character device, not a regular file";
  } else if (S_ISBLK(st.st_mode)) {
    p.reason = "is a block device, not a regular file";
  } else if (S_ISSOCK(st.st_mode)) {
    p.reason = "is a socket, not a regular file";
  } else {
    p.reason = "not a regular file";
  }
  return p;
}

FileProblem too_large(std::uint64_t size, std::uint64_t max_bytes) {
  FileProblem p;
  p.too_large = true;
  p.size = size;
  p.reason = std::to_string(size) + " bytes, over the limit of " + std::to_string(max_bytes);
  return p;
}

struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// Opens `path` without blocking; a device (or, unless pipes are read, a FIFO) is refused
// from its stat before it is opened at all (opening a device can have effects of its own),
// and whatever was opened is checked again by its descriptor.
FileProblem open_checked(const std::filesystem::path& path, Pipes pipes, Descriptor& d, struct stat& st) {
  const bool pipe_ok = pipes == Pipes::Read;
  if (::stat(path.c_str(), &st) != 0) return system_problem(errno);
  if (!(pipe_ok && S_ISFIFO(st.st_mode)))
    if (FileProblem p = kind_problem(st)) return p;
  d.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (d.fd < 0) return system_problem(errno);
  if (::fstat(d.fd, &st) != 0) return system_problem(errno);
  if (pipe_ok && S_ISFIFO(st.st_mode)) return {};
  return kind_problem(st);
}

template <class Bytes>
FileProblem read_all(const std::filesystem::path& path, std::uint64_t max_bytes, Bytes& out, Pipes pipes) {
  out.clear();
  Descriptor d;
  struct stat st {};
  if (FileProblem p = open_checked(path, pipes, d, st)) return p;
  const bool pipe = S_ISFIFO(st.st_mode);
  if (!pipe) {
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (size > max_bytes) return too_large(size, max_bytes);
    // A regular file never blocks; the flag is cleared all the same, as the kernel's
    // behaviour for O_NONBLOCK on files other than pipes is not specified.
    const int flags = ::fcntl(d.fd, F_GETFL);
    if (flags < 0 || ::fcntl(d.fd, F_SETFL, flags & ~O_NONBLOCK) != 0) return system_problem(errno);
    out.resize(static_cast<std::size_t>(size));
    std::size_t done = 0;
    while (done < out.size()) {
      const ssize_t n = ::read(d.fd, out.data() + done, out.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        FileProblem p = system_problem(errno);
        p.reason = std::string("read error: ") + std::strerror(p.error);
        return p;
      }
      if (n == 0) break;  // it shrank while being read: what was there
      done += static_cast<std::size_t>(n);
    }
    out.resize(done);
    return {};
  }
  // A pipe: read until its writers close it (at once when it has none), at most one byte
  // past the limit. Opened non-blocking, so a writer that is there but quiet is waited for
  // with poll.
  FileProblem read_pipe;
  read_pipe.pipe = true;
  std::uint64_t total = 0;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::read(d.fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) {
      pollfd pfd{d.fd, POLLIN, 0};
      if (::poll(&pfd, 1, -1) < 0 && errno != EINTR) return system_problem(errno);
      continue;
    }
    if (n < 0) {
      FileProblem p = system_problem(errno);
      p.reason = std::string("read error: ") + std::strerror(p.error);
      return p;
    }
    if (n == 0) return read_pipe;
    const auto got = static_cast<std::uint64_t>(n);
    const std::uint64_t room = max_bytes - total;  // total <= max_bytes here
    const std::uint64_t keep = room >= got ? got : room + 1;
    out.insert(out.end(), buffer, buffer + keep);
    total += keep;
    if (total > max_bytes) {
      FileProblem p = too_large(total, max_bytes);
      p.pipe = true;
      return p;
    }
  }
}

}  // namespace

FileProblem read_whole_file(const std::filesystem::path& path, std::uint64_t max_bytes, std::vector<std::uint8_t>& out) {
  return read_all(path, max_bytes, out, Pipes::Refuse);
}

FileProblem read_whole_file(const std::filesystem::path& path, std::uint64_t max_bytes, std::string& out, Pipes pipes) {
  return read_all(path, max_bytes, out, pipes);
}

FileProblem file_problem(const std::filesystem::path& path) {
  Descriptor d;
  struct stat st {};
  return open_checked(path, Pipes::Refuse, d, st);
}

}  // namespace softpbr::image
