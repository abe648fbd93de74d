// External files of a .gltf (buffers and images): how a URI names a file, and reading one
// within the loader's limits. Shared by load_gltf (gltf.cpp) and gltf_info (info.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace softpbr::pbr::gltf {

// The path a relative URI reference names (RFC 3986, as glTF 2.0 §3.1 says): its
// percent-encoded octets decoded ("%20" → space; "+" stays "+"; a "%" not followed by two
// hexadecimal digits is kept as it is), joined to base_dir as tinygltf joins buffer paths.
std::string uri_path(const std::string& base_dir, const std::string& uri);

// True for a URI that names an external file (not a data: URI, not empty).
bool is_external_uri(const std::string& uri);

// Reads a whole regular file of at most `limit` bytes that lies inside one of `roots`
// (empty: anywhere) into `out`. Returns "" on success, otherwise one line saying what is
// wrong, starting with the path ("textures/a.png: no such file"). A path holding a NUL
// character (a URI's "%00") is refused. `unreadable`, when given, is set to whether the
// problem is the file itself (missing, not a regular file, no permission: what
// MissingImages::Warn leaves out), not the roots or the size limit.
std::string read_external(const std::string& path, std::uint64_t limit, const std::vector<std::filesystem::path>& roots,
                          std::vector<unsigned char>& out, bool* unreadable = nullptr);

// tinygltf's FsCallbacks::FileExists: whether anything is at `path` (lstat), without
// opening it. tinygltf's own opens the file (fopen), which waits forever on a named pipe
// with no writer; what the thing found is, read_external then says, without blocking.
bool file_exists(const std::string& path, void* user);

}  // namespace softpbr::pbr::gltf
