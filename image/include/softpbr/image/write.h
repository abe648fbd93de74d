// softpbr/image/write.h — writing PNG, Radiance .hdr and OpenEXR images, atomically: each
// file is written under a temporary name in its folder and renamed over the destination,
// so a reader (or a crash) sees the old file or the whole new one, never a partial one.
//
// The encode_* functions return the file's bytes instead (for a .glb buffer, a test, or
// hdr_round_trip). Errors: std::invalid_argument when the image's size and pixel data
// disagree (nothing is written), std::runtime_error starting with the path (or the name)
// when encoding or writing fails.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"

namespace softpbr::image {

// 8-bit RGBA PNG through libspng (zlib level 2, the Sub filter).
std::vector<std::uint8_t> encode_png(const ImageView8& image, std::string_view name);
void write_png(const std::filesystem::path& path, const ImageView8& image);

// The RGB of `image` × `scale` as Radiance RGBE through stb_image_write (alpha dropped;
// values negative or not finite, before or after scaling, are stored as 0). `scale` is an
// exposure (pbr::write_hdr passes 2^stops) applied while encoding, so a render target's
// colour buffer is written without a scaled copy of it.
std::vector<std::uint8_t> encode_hdr(const ImageViewF& image, std::string_view name, float scale = 1.0f);
void write_hdr(const std::filesystem::path& path, const ImageViewF& image, float scale = 1.0f);

// 32-bit float R, G, B × `scale` and A as OpenEXR channels (A, B, G, R, the order most
// readers expect), ZIP compressed, through tinyexr. Values are kept exactly, negatives
// included; non-finite ones become 0.
std::vector<std::uint8_t> encode_exr(const ImageViewF& image, std::string_view name, float scale = 1.0f);
void write_exr(const std::filesystem::path& path, const ImageViewF& image, float scale = 1.0f);

// What an output may be: a new name in an existing folder the process may write, or an
// existing regular file — never a symbolic link, device, named pipe, socket or folder
// (rename() would replace the entry itself: a device node with a regular file) — with a
// name within the folder's NAME_MAX and a path under PATH_MAX. Returns "" when `path` may
// be written, else the problem, "cannot write: …" (without the path). OutputFiles checks
// it; callers check it too before expensive work, so a bad output fails before rendering.
std::string output_problem(const std::filesystem::path& path);

// Several output files replaced all-or-nothing. add() writes each file's bytes completely
// to a temporary file of its own in the destination's folder (an unnamed O_TMPFILE file,
// or where the file system has none a new name ".NAME.tmp-XXXXXXXXXX" created with O_EXCL
// and kept within NAME_MAX), synced to disk; commit() then renames every temporary over
// its destination (an unnamed file whose destination does not exist is linked straight to
// it: a process killed at any point leaves no temporary for a new output). A failure in add() — a full disk, a quota, a file size limit — throws
// with no output replaced; the destructor (or discard()) removes the temporaries this
// object created, and never any other file, so two processes writing the same name do not
// disturb each other (the last rename wins, each file whole). A rename that fails in
// commit() (the folder changed meanwhile) throws naming the outputs already replaced.
class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();

  // Throws std::runtime_error "PATH: …": output_problem(), or the write failed.
  void add(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
  // Checks every destination again (output_problem's entry rule), then renames. Throws
  // std::runtime_error "PATH: …" on failure.
  void commit();
  void discard() noexcept;

 private:
  struct Pending {
    std::filesystem::path path, temporary;  // temporary: empty while the file has no name
    int fd = -1;
  };
  std::vector<Pending> pending_;
};

// One file through OutputFiles: `path` is replaced by the whole of `bytes` or left as it
// was. Throws std::runtime_error naming the path on failure.
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);

}  // namespace softpbr::image
