// json_reader.h — checked reading of untrusted JSON (private to loaders/src): every access
// names the value by its JSON pointer (RFC 6901), every problem is one json_reader::Error
// line "FILE: /pointer: expected …, got …" (scene_file.cpp passes it on as SceneFileError).
#pragma once

#include <cmath>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <utility>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

namespace softpbr::pbr::json_reader {

using Json = nlohmann::json;

// A problem in the document: what() is the one line "FILE: /pointer: what", pointer() the
// JSON pointer ("" for the top level or the text as a whole).
class Error : public std::runtime_error {
 public:
  Error(const std::string& line, std::string pointer) : std::runtime_error(line), pointer_(std::move(pointer)) {}
  const std::string& pointer() const { return pointer_; }

 private:
  std::string pointer_;
};

// A value in the document and its pointer.
struct Node {
  const Json& value;
  std::string pointer;  // "" for the root

  Node child(std::string_view key) const;
  Node at(std::size_t index) const;
};

// The reader of one file: knows its name for messages.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  // Throw Error.
  [[noreturn]] void fail(const Node& node, const std::string& what) const;
  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const;
  const std::string& file() const { return file_; }

  // An object whose keys are all in `allowed` (else: unknown key, with the closest allowed one).
  void object(const Node& node, std::initializer_list<std::string_view> allowed) const;
  // The member `key` of an object node, if present.
  std::optional<Node> member(const Node& node, std::string_view key) const;
  Node required(const Node& node, std::string_view key) const;

  // A finite number in [lo, hi] (inclusive unless open_lo/open_hi), as float or double.
  double number(const Node& node, double lo, double hi, bool open_lo = false, bool open_hi = false) const;
  float number_f(const Node& node, double lo, double hi, bool open_lo = false, bool open_hi = false) const;
  // An integer in [lo, hi].
  long long integer(const Node& node, long long lo, long long hi) const;
  std::string string(const Node& node) const;
  bool boolean(const Node& node) const;
  // One of `names`.
  std::string choice(const Node& node, const std::vector<std::string>& names) const;
  // An array of n numbers in [lo, hi] (finite).
  std::vector<float> numbers(const Node& node, std::size_t n, double lo, double hi) const;
  glm::vec3 vec3(const Node& node, double lo = -1e30, double hi = 1e30) const;
  std::size_t array(const Node& node, std::size_t max_count, const std::string& limit_reason) const;

 private:
  std::string file_;
};

// Structural problems nlohmann's DOM parser would not report: a key that appears twice in
// one object (it keeps the last silently), and nesting deeper than kMaxDepth (the DOM and
// its printing recurse). Found in one iterative SAX pass before the DOM is built; returns
// {pointer, message} of the first, or nothing (also when the text is not valid JSON: the
// DOM parser reports that).
inline constexpr std::size_t kMaxDepth = 32;  // scene files nest 6 deep (a matrix row)
// Values and containers in one file: 100000 objects of a few dozen values each fit; the
// DOM of the largest file allowed stays under about 700 MB.
inline constexpr std::size_t kMaxValues = std::size_t{1} << 23;
inline constexpr std::size_t kMaxContainers = std::size_t{1} << 21;
struct Problem {
  std::string pointer;
  std::string message;
};
// `counts`, when given, receives the number of values, of objects and arrays, and of keys
// seen (up to the first problem or syntax error).
struct Counts {
  std::size_t values = 0, containers = 0, keys = 0;
};
// The limits of a pass: scene files' by default; glTF's are larger (loaders/src/gltf).
struct StructureLimits {
  std::size_t max_depth = kMaxDepth;
  std::size_t max_values = kMaxValues;
  std::size_t max_containers = kMaxContainers;
};
std::optional<Problem> find_structure_problem(std::string_view text, Counts* counts = nullptr,
                                              const StructureLimits& limits = {});

// JSON text of a value for "got …", shortened to about 40 characters.
std::string show(const Json& value);
// A number as written in ranges: 1 → "1", 0.5 → "0.5", 1e30 → "1e+30".
std::string show_number(double x);
// A computed number, to 3 significant digits: 1.00000003e+60 → "1e+60".
std::string show_rounded(double x);
// Pointer escaping of one reference token (~ → ~0, / → ~1).
std::string escape_token(std::string_view key);
// A pointer for messages: each reference token cut to 40 bytes.
std::string shown_pointer(std::string_view pointer);

}  // namespace softpbr::pbr::json_reader
