// softpbr/image/read_file.h — reading a whole input file without ever blocking: the one
// place every softpbr reader (images, environment maps, scene files, OBJ/MTL, glTF and its
// buffers and images, `diff`, the Python module) opens what it reads.
//
// A file is opened with O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC, so that opening a
// named pipe (FIFO) with no writer, or a device, returns at once instead of waiting, then
// fstat'ed: anything but a regular file is refused with its true reason (a FIFO, a
// character device, a folder, ...), and the size limit is checked before a byte is read.
// Only then is O_NONBLOCK cleared and the file read. Checking the descriptor itself, not
// the name, leaves no gap between the check and the read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace softpbr::image {

// Why a file could not be read; empty (false) when it was.
struct FileProblem {
  // One phrase without the file's name, for the caller to put after it: "no such file",
  // "is a folder", "is a named pipe (FIFO), not a regular file", "is a character device,
  // not a regular file", "too many levels of symbolic links (a link loop)", "permission
  // denied", "12345 bytes, over the limit of 4096", "read error: ...".
  std::string reason;
  int error = 0;             // the system's errno for a failed open or read, else 0
  bool folder = false;       // the path is a folder
  bool too_large = false;    // over max_bytes (size holds the file's size)
  std::uint64_t size = 0;
  bool pipe = false;         // (also when read) it was a pipe (Pipes::Read)
  explicit operator bool() const { return !reason.empty(); }
};

// Whether a pipe may be read: the scene file on the command line may be one
// (`softpbr render <(generate-scene)`): it is read until its writer closes it, and a named
// pipe with no writer reads as empty at once. Everything else softpbr reads (models,
// buffers, textures, environment maps, images to compare) must be a regular file.
enum class Pipes { Refuse, Read };

// Reads the whole of `path` (at most max_bytes) into `out`. A file that shrinks while read
// keeps what was there. A pipe (with Pipes::Read) is read up to max_bytes + 1 bytes, so
// that the caller sees it is over the limit (too_large, size = max_bytes + 1).
FileProblem read_whole_file(const std::filesystem::path& path, std::uint64_t max_bytes, std::vector<std::uint8_t>& out);
FileProblem read_whole_file(const std::filesystem::path& path, std::uint64_t max_bytes, std::string& out,
                            Pipes pipes = Pipes::Refuse);

// Why `path` could not be read by read_whole_file (its size not checked), found the same
// way (opened without blocking and closed again), or no problem.
FileProblem file_problem(const std::filesystem::path& path);

}  // namespace softpbr::image
